"""First-frame time: process start to the first pixels, each run in a fresh Python process.

Phases measured inside the child: imports, context (instance, adapter, device),
set-up (shader modules and pipelines: where compilation happens), the first frame
(encode, submit, wait, readback) and a second frame for comparison.

The wgpu child does what ``wgpurender render`` does (the API's ``render``): it starts making the device on a
thread (``context.start_context``) before importing the renderer and the stages, so its ``import_ms`` runs
beside the driver's work and its ``context_ms`` is what is left of making the device after the imports (issue
31.5; benchmarks/startup_split.py times the same steps with the device made in order). The raw child makes its
device after its imports, as the raw path does.

Caches compared ("no caches" clears exactly what :data:`NO_CACHES` says):

- raw path: its VkPipelineCache file (saved at exit, loaded at start) absent vs present;
- both paths: Mesa's on-disk shader cache (the driver's own, below any API) disabled
  ($MESA_SHADER_CACHE_DISABLE) vs warm (a private $MESA_SHADER_CACHE_DIR filled by a
  first run);
- wgpu: wgpu.h's cffi parse, cached by the first run (wgpu_path/device/cdef_cache.py), present (as in every
  second run) vs removed (a first run on the machine);
- wgpu: wgpu-native 0.32 offers the "pipeline-cache" device feature, but neither its C
  header nor wgpu-py 0.32 has a function to create a pipeline cache (wgpu's Rust API has
  ``Device::create_pipeline_cache``), so the wgpu path cannot use one; measured without.

SPIR-V from glslc is cached on disk by the raw path; every configuration here starts
with that cache warm (glslc time is not pipeline creation). Python's bytecode is cached (a private
$PYTHONPYCACHEPREFIX) except in the "no bytecode" rows, which compile every module from source, as a
machine with PYTHONDONTWRITEBYTECODE=1 does (the raw path's ``vulkan`` binding is a 2 MB module).

Run as a child: ``python -m wgpurender.bench.startup wgpu|raw STAGE WxH`` prints JSON.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

T0 = time.perf_counter()

PHASES = ("import_ms", "context_ms", "setup_ms", "first_frame_ms", "second_frame_ms", "total_ms")


def _child(path: str, stage: str, size: tuple[int, int]) -> dict[str, float]:
    marks = {}
    if path == "wgpu":
        from wgpurender.wgpu_path.device.context import get_context, start_context

        start_context()  # as `wgpurender render` does: the device is made while the rest is imported
        from wgpurender.wgpu_path.device.frame_loop import run_frame
        from wgpurender.wgpu_path.device.targets import create_target
        from wgpurender.wgpu_path.stages import get_stage

        cls = get_stage(stage)  # imports the stage modules
        marks["import_ms"] = time.perf_counter()
        ctx = get_context()  # what is left of making it
        marks["context_ms"] = time.perf_counter()
        st = cls(ctx, cls.default_format, None)
        st.resize(size)
        target = create_target(ctx, size, st.format)
        marks["setup_ms"] = time.perf_counter()
        for name in ("first_frame_ms", "second_frame_ms"):
            run_frame(ctx, st.record, target, 0.0)
            marks[name] = time.perf_counter()
    else:
        from wgpurender.bench.raw_frames import RawStageRunner  # no wgpu-py: the raw path's own imports only
        from wgpurender.raw_path.device.context import get_vulkan

        marks["import_ms"] = time.perf_counter()
        get_vulkan()
        marks["context_ms"] = time.perf_counter()
        runner = RawStageRunner(stage, size)
        marks["setup_ms"] = time.perf_counter()
        for name in ("first_frame_ms", "second_frame_ms"):
            runner.frame(readback=True)
            marks[name] = time.perf_counter()
        runner.close()
    out, last = {}, T0
    for name in PHASES[:-1]:
        out[name] = (marks[name] - last) * 1e3
        last = marks[name]
    out["total_ms"] = (marks["first_frame_ms"] - T0) * 1e3  # to the first pixels
    return out


def run_child(path: str, stage: str, size: tuple[int, int], env: dict[str, str]) -> dict[str, float]:
    cmd = [sys.executable, "-m", "wgpurender.bench.startup", path, stage, f"{size[0]}x{size[1]}"]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    if proc.returncode != 0:
        raise RuntimeError(f"startup child failed ({' '.join(cmd)}): {proc.stderr.strip()[-500:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


# wgpu's "no caches" rows start, as a second run of the same command does, with wgpu.h's parse cached
# (wgpu_path/device/cdef_cache.py); this row removes that file first: a first run on the machine.
PARSED = "no caches, wgpu.h parsed (first run)"
NO_BYTECODE = "no caches, no bytecode"
# Exactly what "no caches" clears (issue 31.7), every run: the drivers' shader caches (Mesa's on-disk cache, and
# NVIDIA's, which serves Vulkan too), the raw path's VkPipelineCache file. Kept: Python's bytecode (a fresh
# prefix, compiled by the warming run: an installed package has its .pyc) and glslc's SPIR-V; NO_BYTECODE also
# compiles every module from source, as the GPU machine's image does (PYTHONDONTWRITEBYTECODE=1).
NO_CACHES = ("the drivers' shader caches (Mesa: MESA_SHADER_CACHE_DISABLE; NVIDIA: __GL_SHADER_DISK_CACHE=0) and "
             "the VkPipelineCache file; Python bytecode and SPIR-V cached")


def configurations(work: Path) -> list[tuple[str, str, dict[str, str], bool]]:
    """(path, label, extra env, remove the VkPipelineCache file first)."""
    off = {"MESA_SHADER_CACHE_DISABLE": "true", "__GL_SHADER_DISK_CACHE": "0"}
    warm = {"MESA_SHADER_CACHE_DISABLE": "false", "MESA_SHADER_CACHE_DIR": str(work / "mesa")}
    source = {**off, "PYTHONDONTWRITEBYTECODE": "1", "PYTHONPYCACHEPREFIX": str(work / "no-pyc")}
    return [
        ("wgpu", "no caches", off, True),
        ("wgpu", NO_BYTECODE, source, True),
        ("wgpu", PARSED, off, True),
        ("wgpu", "Mesa shader cache warm", warm, True),
        ("raw", "no caches", off, True),
        ("raw", NO_BYTECODE, source, True),
        ("raw", "VkPipelineCache warm", off, False),
        ("raw", "Mesa shader cache warm", warm, True),
    ]


def _note(label: str) -> str:
    if label == NO_BYTECODE:
        return "fresh process each; cleared: " + NO_CACHES.replace("Python bytecode and SPIR-V cached",
                                                                   "every Python module compiled from source")
    return "fresh process each" + ("; cleared: " + NO_CACHES if label in ("no caches", PARSED) else "")


def bench_startup(stage: str, size: tuple[int, int], repeats: int, quick: bool = False, raw: bool = True,
                  log=print) -> list:
    """Each configuration ``repeats`` times, after one warming run of each. ``quick``: the no-cache rows only."""
    from wgpurender.bench.report import Result, size_text
    from wgpurender.wgpu_path.device.timing import Stats

    out = []
    with tempfile.TemporaryDirectory(prefix="wgpurender-startup-") as tmp:
        work = Path(tmp)
        base = dict(os.environ, XDG_CACHE_HOME=str(work / "xdg"), WGPURENDER_VALIDATION="0",
                    PYTHONPYCACHEPREFIX=str(work / "pyc"))
        base.pop("PYTHONDONTWRITEBYTECODE", None)  # cached bytecode unless a row says otherwise
        base.setdefault("XDG_RUNTIME_DIR", tempfile.gettempdir())
        configs = [c for c in configurations(work) if (raw or c[0] == "wgpu") and (not quick or c[1] == "no caches")]
        import shutil
        for path, _, extra, _ in configs:  # warm every cache once: SPIR-V, VkPipelineCache, Mesa's
            run_child(path, stage, size, {**base, **extra})
        for path, label, extra, cold_vk in configs:
            samples: dict[str, list[float]] = {name: [] for name in PHASES}
            for _ in range(repeats):
                if cold_vk:
                    for f in (work / "xdg" / "wgpurender").glob("vk-pipeline-cache-*.bin"):
                        f.unlink()
                if label == PARSED:
                    for f in (work / "xdg" / "wgpurender").glob("cffi-wgpu-h-*.json"):
                        f.unlink()
                shutil.rmtree(work / "no-pyc", ignore_errors=True)
                result = run_child(path, stage, size, {**base, **extra})
                for name in PHASES:
                    samples[name].append(result[name])
            for name in PHASES:
                out.append(Result.of("startup", f"{stage}: {label}", path, size_text(size), name,
                                     Stats.of(samples[name]), note=_note(label)))
            log(f"  startup: {path} {label}: total {Stats.of(samples['total_ms'])}")
    return out


if __name__ == "__main__":
    w, h = (int(v) for v in sys.argv[3].split("x"))
    print(json.dumps(_child(sys.argv[1], sys.argv[2], (w, h))))
