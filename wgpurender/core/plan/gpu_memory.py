"""How much memory a render's textures take, checked before the first GPU allocation.

``--size 16384x16384`` with MSAA 4 asks for a 4-sample colour image and a 4-sample depth buffer of 268 million
pixels each (over 6 GB); on lavapipe, whose "GPU memory" is the process's own, that ended in a "Not enough memory
left" traceback after minutes of work. The estimate here is plain arithmetic on sizes, formats and sample counts
(what the plan lists, or what a stage makes), and the budget is:

- ``$WGPURENDER_GPU_MEMORY`` (bytes) when set;
- on a CPU adapter (lavapipe, llvmpipe), 80% of the memory the system has available (``MemAvailable``);
- on a GPU, unknown to WebGPU: only the adapter's limits (``max-texture-dimension-2d``) are checked there.

On a CPU adapter one texture may also be at most 2 GiB: lavapipe (Mesa 22.3) reports a single 2 GiB heap and
``maxMemoryAllocationSize`` = 2 GiB (vulkaninfo), and wgpu fails a larger texture with "Not enough memory left"
(measured: the msaa stage at 16384x16384, MSAA 4: a 4.3 GB colour image).
"""

from __future__ import annotations

import os
from collections.abc import Iterable

from wgpurender.core.course.formats import BYTES_PER_PIXEL
from wgpurender.core.errors import UserError
from wgpurender.core.files.input_files import env_limit

GPU_MEMORY_ENV = "WGPURENDER_GPU_MEMORY"
CPU_SHARE = 0.8  # of MemAvailable: the rest is the process, Python, numpy and the readback
CPU_MAX_ALLOCATION = 2**31  # lavapipe's maxMemoryAllocationSize


def texture_bytes(size: tuple[int, int], fmt: str, samples: int = 1) -> int:
    """Bytes of one 2D texture (no padding; a driver may round up a little)."""
    return int(size[0]) * int(size[1]) * BYTES_PER_PIXEL.get(fmt, 16) * max(int(samples), 1)


def plan_textures(plan) -> list[int]:
    """Bytes of each texture a render plan allocates at its size (its attachments, the output included) and of
    the output's readback copy (textures the scene samples are small beside them and not counted)."""
    return [texture_bytes(a.size, a.format, a.sample_count) for a in plan.attachments] + \
        [texture_bytes(plan.size, plan.output_format)]


def plan_bytes(plan) -> int:
    """The sum of :func:`plan_textures`."""
    return sum(plan_textures(plan))


def stage_textures(size: tuple[int, int], fmt: str, msaa: int, depth: bool = True) -> list[int]:
    """A course stage at ``size``: its output, the readback, a multisampled colour image and a depth buffer of
    as many samples (an upper bound: not every stage has depth)."""
    samples = max(int(msaa or 1), 1)
    out = [texture_bytes(size, fmt)] * 2 + ([texture_bytes(size, fmt, samples)] if samples > 1 else [])
    return out + ([texture_bytes(size, "depth32float", samples)] if depth else [])


def _mem_available() -> int | None:
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def budget(adapter_type: str) -> int | None:
    """Bytes a render may allocate on this adapter, or None when not known (a GPU without the env variable)."""
    if os.environ.get(GPU_MEMORY_ENV, "").strip():
        return env_limit(GPU_MEMORY_ENV, 1)
    if adapter_type.upper() == "CPU":
        available = _mem_available()
        return int(available * CPU_SHARE) if available else None
    return None


def _gb(n: int) -> str:
    return f"{n / 1e9:.2f} GB" if n >= 1e8 else f"{n / 1e6:.1f} MB"


def describe(needed: int) -> str:
    """The line ``--explain`` prints."""
    return f"about {_gb(needed)} of attachments and readback (checked before allocation against the adapter's " \
           f"memory: ${GPU_MEMORY_ENV}, or 80% of available memory on a CPU adapter)"


def check_memory(textures: list[int], adapter_type: str, what: str) -> None:
    """UserError when the textures (bytes each) exceed the adapter's budget, or one of them the largest
    allocation a CPU adapter makes; nothing when the budget is unknown."""
    needed, largest = sum(textures), max(textures, default=0)
    if adapter_type.upper() == "CPU" and largest > CPU_MAX_ALLOCATION and not os.environ.get(GPU_MEMORY_ENV):
        raise UserError(f"{what} needs a texture of {_gb(largest)}, over the {_gb(CPU_MAX_ALLOCATION)} a CPU adapter "
                        "(lavapipe) allocates at once; choose a smaller --size or --msaa 1")
    limit = budget(adapter_type)
    if limit is not None and needed > limit:
        raise UserError(f"{what} needs about {_gb(needed)} of GPU memory for its attachments, more than this "
                        f"adapter has ({_gb(limit)}{' available' if adapter_type.upper() == 'CPU' else ''}); "
                        f"choose a smaller --size or --msaa 1, or set ${GPU_MEMORY_ENV}=BYTES if there is more")


def check_dimensions(sizes: Iterable[tuple[int, int]], max_dimension: int, what: str) -> None:
    """UserError when a texture side exceeds the adapter's max-texture-dimension-2d."""
    for w, h in sizes:
        if max(w, h) > max_dimension:
            raise UserError(f"{what}: size {w}x{h} is larger than this adapter's max-texture-dimension-2d "
                            f"({max_dimension}): choose a smaller --size")
