"""A scene file in the benchmark: the wgpu scene renderer and, where it can draw the scene, the raw path's.

Both are drawn frame by frame into one target (the runner protocol of :func:`frames.measure`).
Per-pass GPU times on the wgpu side (scene pass, each post pass) come from the renderer's own
``timer`` argument. The raw-Vulkan path (wgpurender/raw_path/scene/) draws a scene in one
render pass of two subpasses, plus a render pass per effect that reads neighbouring pixels (FXAA,
sharpen), so both ``final.toml`` and ``final_subpass.toml`` (the same scene, per-pixel chain only)
have raw peers; a scene the raw path refuses is timed on wgpu only, with a note saying why. The two paths run in
alternating rounds (frames.measure_interleaved); wgpu's timestamps are read once at the end (PassTimer(frames=N)).
"""

from __future__ import annotations

import functools
from pathlib import Path

from wgpurender.bench.encoder import gpu_total
from wgpurender.bench.frames import TIMER_SLOTS, RawStageRunner, measure, measure_interleaved
from wgpurender.bench.report import Result, command_line, size_text
from wgpurender.core.files.assets import resolve_scene
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.device.timing import Stats


class SceneRunner:
    """A persistent scene renderer drawn frame by frame (the runner protocol of frames.measure)."""

    def __init__(self, ctx: GPUContext, path: Path, size: tuple[int, int],
                 anisotropy: str = DEFAULT_ANISOTROPY) -> None:
        from wgpurender.wgpu_path.device.timing import PassTimer
        from wgpurender.wgpu_path.scene import load_renderer

        self.ctx = ctx
        self.renderer = load_renderer(path, ctx, size=size, anisotropy=anisotropy)  # resolve_plan's plan
        self.target = self.renderer.create_output()
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


class _RawSceneFrame:
    """A raw-path scene frame with the stage interface ``record(cmd, target, t)`` (scenes are static)."""

    def __init__(self, frame) -> None:
        self.frame = frame

    def record(self, cmd, target, t: float = 0.0) -> None:
        self.frame.record(cmd, target)


class RawSceneRunner(RawStageRunner):
    """The raw-Vulkan path's scene frame (raw_path/scene/), frame after frame, like a raw stage."""

    def __init__(self, path: Path, size: tuple[int, int], anisotropy: str = DEFAULT_ANISOTROPY) -> None:
        from contextlib import ExitStack

        from wgpurender.core.plan import resolve_plan
        from wgpurender.core.scene import load_scene
        from wgpurender.raw_path.device.checks import check_size
        from wgpurender.raw_path.device.context import get_vulkan
        from wgpurender.raw_path.scene.frame import SceneFrame

        ctx = get_vulkan()
        scene = load_scene(path)
        plan = resolve_plan(scene, ctx.adapter_facts(), size=size, anisotropy=anisotropy)
        self.name = str(path)
        self.size = check_size(ctx, plan.size)
        self.owned = ExitStack()
        self.stage = _RawSceneFrame(SceneFrame(ctx, self.owned, scene, plan))
        self._setup_frames(ctx, plan.output_format)


def raw_refusal(path: Path) -> str:
    """Why the raw path cannot draw this scene ('' when it can)."""
    from wgpurender.core.plan import resolve_plan
    from wgpurender.raw_path.scene import unsupported

    return "; ".join(unsupported(resolve_plan(path, None)))


def bench_scene(ctx: GPUContext, path: Path, size: tuple[int, int], frames: int,
                raw: bool = True, anisotropy: str = DEFAULT_ANISOTROPY) -> tuple[list[Result], str]:
    """(results, note): the wgpu renderer, and the raw path's when ``raw`` and it can draw the scene, each
    drawing the plan :func:`wgpurender.core.plan.resolve_plan` resolves for its adapter.

    A note with no results means skipped (the scene file is absent); a note with results says why
    the raw peer is missing.
    """
    path = resolve_scene(path)  # a bundled scene's name or repository path works from any folder
    if not path.is_file():
        return [], f"skipped: scene file {path} not found"
    runner = SceneRunner(ctx, path, size, anisotropy)
    readback_frames = max(3, frames // 2)
    refusal = raw_refusal(path) if raw else ""
    if not raw or refusal:
        samples = {"wgpu": measure(runner, frames, readback_frames=readback_frames)}
    else:
        with RawSceneRunner(path, size, anisotropy) as raw_runner:
            samples = measure_interleaved({"wgpu": runner, "raw": raw_runner}, frames, readback_frames)
    results = [r for p, smp in samples.items() for r in smp.results("scene", path.stem, p, size)]
    results += untimed_results(ctx, runner, path.stem, size, frames)
    record_passes(ctx, runner, path.stem, size, frames)
    for label, ms in runner.passes.items():
        results.append(Result.of("scene", path.stem, "wgpu", size_text(size), f"gpu_ms:{label}",
                                 Stats.of(ms[-frames:]), "GPU time of one pass"))
    return results, (f"{path.name} has no raw peer: {refusal}" if refusal else "")


def untimed_results(ctx: GPUContext, runner: SceneRunner, case: str, size: tuple[int, int],
                    frames: int) -> list[Result]:
    """The frame as a window makes it (no pass timestamps, no readback): CPU record + submit, and its native
    calls counted by wrapping the device, queue and encoders (bench/calls.py)."""
    from wgpurender.bench.calls import call_profile, steady_calls

    cpu = []
    for _ in range(frames + 2):
        cpu.append(run_frame(ctx, runner.renderer.record, runner.target, runner.t, label="bench-scene",
                             read_back=False, wait=True).cpu_ms)
    calls = steady_calls(ctx, runner.renderer.record, runner.target)
    n = sum(calls.values())
    detail = ", ".join(f"{k} {v}" for k, v in sorted(calls.items()))
    detail += ("; CPU us per frame by call (mean of 10 counted frames, the counting's overhead in 'python'): "
               + call_profile(ctx, runner.renderer.record, runner.target))
    s = size_text(size)
    return [Result.of("scene", case, "wgpu", s, "cpu_ms:untimed", Stats.of(cpu[2:]),
                      "record + submit of the frame without pass timestamps (as a window draws it)"),
            Result("scene", case, "wgpu", s, "native_calls", n, n, n, 1, f"per steady-state frame: {detail}")]


def record_passes(ctx: GPUContext, runner: SceneRunner, scene: str, size: tuple[int, int], frames: int) -> None:
    """Each pass's median GPU time beside a same-run copy of its bytes, for ``render --explain``
    (core/files/bandwidth.py)."""
    import datetime
    import statistics

    from wgpurender.bench.post_roofline import CopyKernel, dispatch_bytes
    from wgpurender.core.files import bandwidth
    from wgpurender.core.plan.explain import scene_pass_bytes

    if not runner.passes or not ctx.has("timestamp-query"):
        return
    plan = runner.renderer.plan
    moved = {("scene", "render"): sum(scene_pass_bytes(plan))}
    moved.update({(p.effect, p.path): dispatch_bytes(p, size)[0] for p in plan.post_passes})
    copy, date = CopyKernel(ctx), datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    records = {}
    for (effect, path), n in moved.items():
        label = "scene" if effect == "scene" else f"post:{effect}"
        if label in runner.passes and n > 0:
            ms = statistics.median(runner.passes[label][-frames:])
            records[bandwidth.pass_key(scene, effect, path)] = bandwidth.PassRecord(
                ms, n / 1e6, copy.ms(n, frames), size_text(size), date, command_line())
    bandwidth.save(ctx.info.get("device", ""), records)
