"""Headless rendering: a stage into an offscreen target, read back into numpy."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .gpu import GPUContext, get_context
from .stages import get_stage
from .targets import check_format, create_target, read_texture


@dataclass
class RenderResult:
    pixels: np.ndarray
    frame_ms: float  # wall time of one steady-state frame: encode, submit, GPU, readback
    adapter: str


def render_stage(
    name: str,
    size: tuple[int, int] = (800, 600),
    fmt: str | None = None,
    msaa: int | None = None,
    t: float = 0.0,
    ctx: GPUContext | None = None,
    frames: int = 2,
) -> RenderResult:
    """Render ``frames`` frames of a stage headless and return the last one.

    The first frame pays for lazy driver work (shader JIT on lavapipe), so the
    reported time is the last frame's.
    """
    ctx = ctx or get_context()
    cls = get_stage(name)
    fmt = check_format(fmt or cls.default_format)
    stage = cls(ctx, fmt, msaa)
    stage.resize(size)
    target = create_target(ctx, size, fmt)
    frame_ms = 0.0
    pixels = None
    for _ in range(max(1, frames)):
        start = time.perf_counter()
        encoder = ctx.device.create_command_encoder(label=f"{name}-frame")
        stage.draw(encoder, target, t)
        ctx.queue.submit([encoder.finish()])
        pixels = read_texture(ctx, target)
        frame_ms = (time.perf_counter() - start) * 1e3
    return RenderResult(pixels=pixels, frame_ms=frame_ms, adapter=ctx.describe())


def render_any(
    target: str,
    size: tuple[int, int] | None = None,
    fmt: str | None = None,
    msaa: int | None = None,
    t: float = 0.0,
    backend: str | None = None,
) -> RenderResult:
    """A stage by name, or a scene file when ``target`` ends in .toml."""
    ctx = get_context(backend)
    if target.endswith(".toml"):
        from .scene_render import render_scene_file  # the final-scene renderer

        return render_scene_file(target, size=size, fmt=fmt, msaa=msaa, t=t, ctx=ctx)
    return render_stage(target, size or (800, 600), fmt, msaa, t, ctx)
