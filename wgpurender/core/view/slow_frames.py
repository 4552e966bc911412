"""Why a window frame is slow: printed once, with what to change, when a frame takes more than a few seconds.

A window on a CPU driver (lavapipe) can take many seconds per frame and look frozen: e.g.
vulkan_tutorial_28.toml took 19.9 s a frame at 96x72, because anisotropy 16 on a texture with one mip level
makes llvmpipe take up to 16 full-resolution taps per sample, every pixel. The window loop calls :func:`tick`
after each frame; the first frame slower than :data:`SLOW_FRAME_SECONDS` (after the first, which pays for shader
compilation) prints one line to stderr naming the likely cause and the setting to change.
"""

from __future__ import annotations

import sys
import time
import weakref

SLOW_FRAME_SECONDS = 3.0
# Per drawable, held weakly: keyed by id() a new drawable could inherit a dead one's state (ids are reused), and a
# window that rebuilds its drawable on live reload would keep every old one alive.
_last: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # drawable -> time of its previous frame
_told: weakref.WeakSet = weakref.WeakSet()  # drawables whose slow frame was explained


def tick(ctx, drawable, size: tuple[int, int], now: float | None = None) -> str | None:
    """Call once per presented frame. Returns (and prints once per drawable) the explanation of a slow frame."""
    now = time.perf_counter() if now is None else now
    previous = _last.get(drawable)
    _last[drawable] = now
    if previous is None or drawable in _told or now - previous < SLOW_FRAME_SECONDS:
        return None
    _told.add(drawable)
    message = f"wgpurender: a frame took {now - previous:.1f} s at {size[0]}x{size[1]}: {explain(ctx, drawable, size)}"
    print(message, file=sys.stderr)
    return message


def _cpu_driver(ctx) -> bool:
    info = getattr(getattr(ctx, "adapter", None), "info", {}) or {}
    text = f"{info.get('adapter_type', '')} {info.get('device', '')} {info.get('description', '')}".lower()
    return "cpu" in text or "llvmpipe" in text or "lavapipe" in text or "swiftshader" in text


def _anisotropic_without_mips(scene) -> list[tuple[str, int]]:
    """(where, anisotropy) of every textured material that samples anisotropically with one mip level."""
    materials = {m.origin: m for m in scene.materials.values()}
    materials.update({m.material.origin: m.material for m in scene.models})
    return [(origin, m.sampler.anisotropy) for origin, m in materials.items()
            if m.textures and m.sampler.anisotropy > 1 and not m.sampler.mipmaps]


def explain(ctx, drawable, size: tuple[int, int]) -> str:
    """The likeliest cause of a slow frame and what to change, in one sentence."""
    cpu = _cpu_driver(ctx)
    driver = "a CPU driver (lavapipe)" if cpu else "this GPU"
    scene = getattr(drawable, "scene", None)
    if scene is not None:
        found = _anisotropic_without_mips(scene)
        if found:
            where, level = found[0]
            return (f"anisotropic filtering ({level}x) without mip maps on {driver}, in {where}: set "
                    "anisotropy = 1 or mipmaps = true in its sampler")
        plan = getattr(drawable, "plan", None)
        if cpu and plan is not None and getattr(plan, "msaa", 1) > 1:
            return f"{plan.msaa}x MSAA on {driver}: set [render] msaa = 1, or make the window smaller"
    return f"the window is {size[0]}x{size[1]} on {driver}: make the window smaller" + (
        "" if cpu else ", or check what else is using the GPU")
