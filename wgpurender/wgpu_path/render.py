"""Headless rendering: a stage (or a scene file) into an offscreen target, read back into numpy."""

from __future__ import annotations

from collections.abc import Iterator, Sequence

from wgpurender.core.course.formats import is_scene_file
from wgpurender.core.plan import gpu_memory
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.wgpu_path.device.context import GPUContext, get_context
from wgpurender.wgpu_path.device.frame_loop import Frame, RenderResult, run_frames
from wgpurender.wgpu_path.device.targets import check_format, create_target
from wgpurender.wgpu_path.stages import get_stage
from wgpurender.wgpu_path.stages.base import Stage

__all__ = ["RenderResult", "render_any", "render_stage", "render_stage_class"]


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
    frame = next(render_stage_class(get_stage(name), size, fmt, msaa, (t,), ctx, frames))
    return RenderResult(pixels=frame.pixels, frame_ms=frame.frame_ms, adapter=ctx.describe())


def render_stage_class(cls: type[Stage], size: tuple[int, int], fmt: str | None, msaa: int | None,
                       times: Sequence[float], ctx: GPUContext, frames: int = 1) -> Iterator[Frame]:
    """One stage object of ``cls`` (a registered stage, or a learner's: wgpurender/exercises/), set up once, its
    frame at each of ``times`` (``frames`` frames each, the last kept)."""
    name = cls.name
    fmt = check_format(fmt or cls.default_format)
    stage = cls(ctx, fmt, msaa)
    gpu_memory.check_dimensions([size], ctx.limit("max-texture-dimension-2d"), f"stage {name}")
    gpu_memory.check_memory(gpu_memory.stage_textures(size, fmt, stage.msaa), ctx.adapter.info["adapter_type"],
                            f"stage {name} at {size[0]}x{size[1]}, msaa {stage.msaa}")
    stage.resize(size)
    target = create_target(ctx, size, fmt)
    for t in times:
        yield run_frames(ctx, stage.record, target, frames, t, label=f"{name}-frame")


def render_any(
    target: str,
    size: tuple[int, int] | None = None,
    fmt: str | None = None,
    msaa: int | None = None,
    t: float = 0.0,
    backend: str | None = None,
    anisotropy: str = DEFAULT_ANISOTROPY,
) -> RenderResult:
    """A stage by name, or a scene file (:func:`wgpurender.core.course.formats.is_scene_file`).

    ``anisotropy``: "scene" or "auto" (per adapter, wgpurender/core/plan/anisotropy.py), for scene files."""
    ctx = get_context(backend)
    if is_scene_file(target):
        from wgpurender.wgpu_path.scene import render_scene_file  # the final-scene renderer

        return render_scene_file(target, size=size, fmt=fmt, msaa=msaa, t=t, ctx=ctx, anisotropy=anisotropy)
    return render_stage(target, size or (800, 600), fmt, msaa, t, ctx)
