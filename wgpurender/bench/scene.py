"""The final scene in the benchmark, when the final-scene renderer exists (wgpurender.scene_render).

Imported lazily: without the renderer (or the scene file) the family is skipped with a
note. The renderer's per-frame API is discovered, not assumed: an object with
``record(encoder, target, t)`` (like a stage) is timed frame by frame; otherwise whole
``render_scene_file`` calls are timed (set-up included, said in the note).
The raw path takes part only if it has a stage named ``final``. Per-pass GPU times (scene pass,
each post pass) come from the renderer's own ``timer`` argument.
"""

from __future__ import annotations

import functools
import importlib.util
import time
from pathlib import Path

from ..frame_loop import run_frame
from ..gpu import GPUContext
from ..timing import Stats
from .encoder import gpu_total
from .frames import RawStageRunner, measure
from .report import Result, size_text

RAW_SCENE_STAGE = "final"


def scene_renderer_available() -> bool:
    return importlib.util.find_spec("wgpurender.scene_render") is not None


def _raw_has_scene() -> bool:
    from ..vulkan_ref import reference_stage_names

    return RAW_SCENE_STAGE in reference_stage_names()


class SceneRunner:
    """A persistent scene renderer drawn frame by frame (the runner protocol of frames.measure)."""

    def __init__(self, ctx: GPUContext, renderer, target) -> None:
        from ..timing import PassTimer

        self.ctx, self.renderer, self.target = ctx, renderer, target
        self.timer = PassTimer(ctx)
        self.t = 0.0
        self.passes: dict[str, list[float]] = {}  # GPU ms per pass label, per frame

    def frame(self, readback: bool = False) -> tuple[float, float | None]:
        f = run_frame(self.ctx, functools.partial(self.renderer.record, timer=self.timer), self.target, self.t,
                      label="bench-scene", read_back=readback, timer=self.timer)
        for label, ms in f.gpu_ms.items():
            self.passes.setdefault(label, []).append(ms)
        return f.cpu_ms, gpu_total(f.gpu_ms)


def _make_renderer(module, ctx: GPUContext, path: Path, size: tuple[int, int]):
    """A (renderer, target) pair if the module offers a per-frame renderer, else None."""
    load = getattr(module, "load_renderer", None)
    if load is None:
        return None
    from ..targets import create_target

    renderer = load(path, ctx, size=size)
    plan = getattr(renderer, "plan", None)
    fmt = getattr(plan, "output_format", None) or "rgba8unorm-srgb"
    return renderer, create_target(ctx, size, fmt)


def bench_scene(ctx: GPUContext, path: Path, size: tuple[int, int], frames: int,
                raw: bool = True) -> tuple[list[Result], str]:
    """(results, note); a non-empty note with no results means skipped."""
    if not scene_renderer_available():
        return [], "skipped: wgpurender.scene_render does not exist yet (final-scene renderer not landed)"
    path = Path(path)
    if not path.is_file():
        return [], f"skipped: scene file {path} not found"
    import importlib

    module = importlib.import_module("wgpurender.scene_render")
    made = _make_renderer(module, ctx, path, size)
    results: list[Result] = []
    note = ""
    if made is not None:
        runner = SceneRunner(ctx, *made)
        results += measure(runner, frames, readback_frames=max(3, frames // 2)).results("scene", path.stem,
                                                                                        "wgpu", size)
        for label, samples in runner.passes.items():
            results.append(Result.of("scene", path.stem, "wgpu", size_text(size), f"gpu_ms:{label}",
                                     Stats.of(samples[-frames:]), "GPU time of one pass"))
    else:
        samples = []
        for _ in range(max(3, frames // 2)):
            start = time.perf_counter()
            module.render_scene_file(str(path), size=size, ctx=ctx)
            samples.append((time.perf_counter() - start) * 1e3)
        note = "render_scene_file per frame: set-up and readback included (no per-frame renderer API found)"
        results.append(Result.of("scene", path.stem, "wgpu", size_text(size), "frame_readback_ms",
                                 Stats.of(samples), note))
    if raw and _raw_has_scene():
        with RawStageRunner(RAW_SCENE_STAGE, size) as raw_runner:
            results += measure(raw_runner, frames, readback_frames=max(3, frames // 2)).results(
                "scene", path.stem, "raw", size)
    return results, note if not results else ""
