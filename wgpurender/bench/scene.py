"""The final scene in the benchmark, when the final-scene renderer exists (wgpurender.scene_render).

Imported lazily: without the renderer (or the scene file) the family is skipped with a
note. The renderer's per-frame API is discovered, not assumed: an object with
``record(encoder, target, t)`` (like a stage) is timed frame by frame; otherwise whole
``render_scene_file`` calls are timed (set-up included, said in the note).
The raw path draws the same scene file with its own renderer (vulkan_ref/scene: one render pass,
the post chain as a second subpass) where it can (``vulkan_ref.scene.unsupported`` says why not,
e.g. FXAA before the raw path had it); the two run in alternating rounds. Per-pass GPU times
(scene pass, each post pass) come from the renderer's own ``timer`` argument.
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
from .frames import RawStageRunner, measure, measure_interleaved
from .report import Result, size_text


def scene_renderer_available() -> bool:
    return importlib.util.find_spec("wgpurender.scene_render") is not None


class _RawScene:
    """The raw path's scene frame in the stage protocol of frames.RawStageRunner."""

    def __init__(self, frame, fmt: str) -> None:
        self.frame, self.format = frame, fmt

    def record(self, cmd, target, t: float = 0.0) -> None:
        self.frame.record(cmd, target)


def raw_scene_runner(path: Path, size: tuple[int, int]) -> tuple[RawStageRunner | None, str]:
    """(a raw-Vulkan runner of the scene file, "") or (None, why the raw path cannot draw it)."""
    from ..plan import build_plan
    from ..scene import load_scene
    from ..vulkan_ref.scene import unsupported
    from ..vulkan_ref.scene.frame import SceneFrame

    scene = load_scene(path)
    plan = build_plan(scene, size=size)
    problems = unsupported(plan)
    if problems:
        return None, f"no raw peer for {path.name}: " + "; ".join(problems)
    return RawStageRunner(path.stem, size, make_stage=lambda ctx, owned: _RawScene(
        SceneFrame(ctx, owned, scene, plan), plan.output_format)), ""


class SceneRunner:
    """A persistent scene renderer drawn frame by frame (the runner protocol of frames.measure)."""

    def __init__(self, ctx: GPUContext, renderer, target) -> None:
        from ..timing import PassTimer
        from .frames import TIMER_SLOTS

        self.ctx, self.renderer, self.target = ctx, renderer, target
        self.timer = PassTimer(ctx, frames=TIMER_SLOTS)
        self.t = 0.0
        self.passes: dict[str, list[float]] = {}  # GPU ms per pass label, per frame

    def frame(self, readback: bool = False) -> tuple[float, float | None]:
        f = run_frame(self.ctx, functools.partial(self.renderer.record, timer=self.timer), self.target, self.t,
                      label="bench-scene", read_back=readback, timer=self.timer)
        return f.cpu_ms, None

    def collect_gpu(self) -> list[float | None]:
        """GPU ms of every frame since the last call (and each pass's time into ``passes``)."""
        frames = self.timer.collect()
        for gpu in frames:
            for label, ms in gpu.items():
                self.passes.setdefault(label, []).append(ms)
        return [gpu_total(g) for g in frames]


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
        raw_runner, why = raw_scene_runner(path, size) if raw else (None, "")
        readback = max(3, frames // 2)
        if raw_runner is None:
            samples = {"wgpu": measure(runner, frames, readback_frames=readback)}
            note = why
        else:
            with raw_runner:
                samples = measure_interleaved({"wgpu": runner, "raw": raw_runner}, frames, readback)
        for p, smp in samples.items():
            results += smp.results("scene", path.stem, p, size)
        for label, ms in runner.passes.items():
            results.append(Result.of("scene", path.stem, "wgpu", size_text(size), f"gpu_ms:{label}",
                                     Stats.of(ms[-frames:]), "GPU time of one pass"))
        return results, note
    samples = []
    for _ in range(max(3, frames // 2)):
        start = time.perf_counter()
        module.render_scene_file(str(path), size=size, ctx=ctx)
        samples.append((time.perf_counter() - start) * 1e3)
    note = "render_scene_file per frame: set-up and readback included (no per-frame renderer API found)"
    results.append(Result.of("scene", path.stem, "wgpu", size_text(size), "frame_readback_ms", Stats.of(samples), note))
    return results, note
