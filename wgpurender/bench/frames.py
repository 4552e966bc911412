"""Frame time of a stage on the wgpu path and on the raw-Vulkan path, set up once and drawn N times.

Per frame both paths do the same: record the stage's commands, submit once, wait for
the GPU on the calling thread (wgpu: ``ctx.wait_idle``, i.e. wgpuDevicePoll; raw: a
fence), optionally with the copy of the image to a reused host buffer recorded into the
same command buffer, then read it. Timestamps are resolved every frame on both paths;
wgpu reads them for all frames at the end (PassTimer(frames=N): mapping a buffer per
frame costs more than the raw path's vkGetQueryPoolResults). The two paths run in
alternating rounds (:func:`measure_interleaved`), so a load change on a shared machine
hits both. Measured per frame:

- ``frame_ms``: wall time of record + submit + wait (no readback);
- ``cpu_ms``: wall time of record + submit alone (what the CPU spends per frame);
- ``gpu_ms``: GPU timestamps around the stage's passes (wgpu: start and end of each
  pass, summed; raw: vkCmdWriteTimestamp before and after the stage's commands);
- ``readback_ms``: paired: a frame with readback right after a frame without, the
  median of the differences (p10..p90 of the differences as the spread).

The raw runner builds on the raw_path modules (stage classes, images, command
pools) and needs no change there: a stage's ``record`` may be called once per
frame (it makes a framebuffer each time, registered with the stage's ExitStack;
a small per-frame cost the raw path pays and wgpu does not).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from wgpurender.bench.encoder import gpu_total, timed_frame
from wgpurender.bench.raw_frames import RawStageRunner  # re-exported: the bench's raw peer
from wgpurender.bench.report import Result, size_text
from wgpurender.core.view import garbage
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.timing import PassTimer, Stats

TIMER_SLOTS = 1024  # frames between two PassTimer.collect() calls: far more than one measure() makes


@dataclass
class Samples:
    """Per-frame samples of one runner, in milliseconds."""

    frame: list[float] = field(default_factory=list)
    cpu: list[float] = field(default_factory=list)
    gpu: list[float] = field(default_factory=list)
    readback_frame: list[float] = field(default_factory=list)
    readback_pair: list[float] = field(default_factory=list)  # readback frame minus the frame just before

    def extend(self, other: Samples) -> None:
        for name in ("frame", "cpu", "gpu", "readback_frame", "readback_pair"):
            getattr(self, name).extend(getattr(other, name))

    def results(self, family: str, case: str, path: str, size: tuple[int, int], note: str = "") -> list[Result]:
        s = size_text(size)
        out = [Result.of(family, case, path, s, "frame_ms", Stats.of(self.frame), note),
               Result.of(family, case, path, s, "cpu_ms", Stats.of(self.cpu), note)]
        if self.gpu:
            out.append(Result.of(family, case, path, s, "gpu_ms", Stats.of(self.gpu), note))
        if self.readback_frame:
            out.append(Result.of(family, case, path, s, "frame_readback_ms", Stats.of(self.readback_frame), note))
            out.append(readback_result(family, case, path, s, self.readback_pair))
        return out


def readback_result(family: str, case: str, path: str, size: str, pairs: list[float]) -> Result:
    """The readback cost from paired frames; a median below zero (readback lost in the noise) reads 0."""
    st = Stats.of(pairs)
    note = "median of (frame with readback - the frame just before it)"
    if st.median < 0:
        note += f"; measured {st.median:.3f} ms: below the noise, shown as 0"
    return Result(family, case, path, size, "readback_ms", max(0.0, st.median), max(0.0, st.p10), max(0.0, st.p90),
                  st.n, note)


def _timed(runner, readback: bool = False) -> tuple[float, float, float | None]:
    start = time.perf_counter()
    cpu_ms, gpu_ms = runner.frame(readback=readback)
    return (time.perf_counter() - start) * 1e3, cpu_ms, gpu_ms


GC_ENV = "WGPURENDER_BENCH_GC"


def settle_garbage() -> None:
    """Before timed frames: collect and freeze what set-up made (``gc.freeze``), so no collection ever scans
    the renderer's objects again; what an application should do after loading a scene (docs/benchmarks.md).
    $WGPURENDER_BENCH_GC=default leaves the collector as Python sets it (the 4-5 ms tails of issue 22)."""
    import os

    if os.environ.get(GC_ENV) != "default":
        garbage.settle()  # the windows' rule (core/view/garbage.py)


class frames_without_gc:
    """The collector paused for the timed frames (a frame allocates a few hundred small objects; a collection
    runs after the block, outside the timings), unless $WGPURENDER_BENCH_GC=default."""

    def __enter__(self) -> None:
        import gc
        import os

        self.was = gc.isenabled()
        if os.environ.get(GC_ENV) != "default":
            gc.disable()

    def __exit__(self, *exc) -> None:
        import gc

        if self.was:
            gc.enable()
        garbage.thaw()  # the next case's settle_garbage collects what this one left, then freezes again


WARM_WINDOW, WARM_SPREAD, WARM_MAX_FRAMES, WARM_BUDGET_S = 4, 1.25, 60, 3.0


def warm_up(runner, min_frames: int = 2) -> int:
    """Untimed frames until the frame time is stable: the last :data:`WARM_WINDOW` frames within
    :data:`WARM_SPREAD` x of each other (at least ``min_frames``; at most :data:`WARM_MAX_FRAMES` frames or
    :data:`WARM_BUDGET_S` seconds). A fixed count was not enough: a GPU-animated 1M-object frame read 32 ms
    after one warm-up frame and 5.8 ms after ten (issue 31.7). Returns the number of frames drawn."""
    times: list[float] = []
    start = time.perf_counter()
    while True:
        t = time.perf_counter()
        runner.frame()
        times.append(time.perf_counter() - t)
        last = times[-WARM_WINDOW:]
        if len(times) >= max(min_frames, WARM_WINDOW) and max(last) <= WARM_SPREAD * min(last):
            return len(times)
        if len(times) >= WARM_MAX_FRAMES or time.perf_counter() - start > WARM_BUDGET_S:
            return len(times)


def measure(runner, frames: int, warmup: int = 2, readback_frames: int = 0) -> Samples:
    """Warm-up frames until stable (:func:`warm_up`, at least ``warmup``), then ``frames`` timed ones, then
    ``readback_frames`` pairs: a frame without readback right before one with (the readback cost is their
    difference). A runner with ``collect_gpu()`` reports GPU times at the end. The collector is frozen before and
    paused during the timed frames (:func:`settle_garbage`, :func:`frames_without_gc`).

    Nothing the bench does itself comes between two samples (issue 31.4, p99 <= 2x the median;
    benchmarks/tail_probe.py shows both on lavapipe and the H100):

    - the collection and the timestamp read come before the warm-up, so the first timed frame follows warm frames
      as every other does (after them it was each round's slowest: on lavapipe 6-17 ms against medians of 0.2-0.4
      ms, 4 of 100 samples, so the p99); the warm-up frames' timestamps are dropped when the samples' are read;
    - the readback pairs come after the samples: a frame right after a readback frame (a large copy through the
      host's caches) is not a sample of a frame without readback."""
    settle_garbage()
    collect = getattr(runner, "collect_gpu", None)
    if collect is not None:
        collect()  # drop earlier frames' timestamps
    warmed = warm_up(runner, warmup)
    with frames_without_gc():
        return _timed_frames(runner, frames, readback_frames, collect, warmed)


def _timed_frames(runner, frames: int, readback_frames: int, collect, untimed: int = 0) -> Samples:
    """``untimed``: frames drawn since the last ``collect()`` that are not samples (their timestamps are dropped)."""
    samples, kinds = Samples(), [False] * untimed
    for _ in range(frames):
        frame_ms, cpu_ms, gpu_ms = _timed(runner)
        samples.frame.append(frame_ms)
        samples.cpu.append(cpu_ms)
        kinds.append(True)
        if gpu_ms is not None:
            samples.gpu.append(gpu_ms)
    for _ in range(readback_frames):
        plain_ms, _, _ = _timed(runner)
        with_rb, _, _ = _timed(runner, readback=True)
        samples.readback_frame.append(with_rb)
        samples.readback_pair.append(with_rb - plain_ms)
        kinds += [False, False]
    if collect is not None:
        samples.gpu = [g for g, plain in zip(collect(), kinds, strict=False) if plain and g is not None]
    return samples


def measure_interleaved(runners: dict[str, object], frames: int, readback_frames: int = 0,
                        rounds: int = 4) -> dict[str, Samples]:
    """:func:`measure` for each runner in ``rounds`` alternating rounds (the order flips each round)."""
    names = list(runners)
    out = {name: Samples() for name in names}
    per, rb = max(1, frames // rounds), max(0, -(-readback_frames // rounds))
    for k in range(rounds):
        for name in (names if k % 2 == 0 else names[::-1]):
            out[name].extend(measure(runners[name], per, warmup=2 if k == 0 else 1, readback_frames=rb))
    return out


# -- wgpu ---------------------------------------------------------------------------------------


class WgpuStageRunner:
    """A wgpu stage drawn into one offscreen target, frame after frame."""

    def __init__(self, ctx: GPUContext, name: str, size: tuple[int, int], fmt: str | None = None,
                 msaa: int | None = None) -> None:
        from wgpurender.wgpu_path.device.targets import create_target
        from wgpurender.wgpu_path.stages import get_stage

        cls = get_stage(name)
        self.ctx = ctx
        self.name = name
        self.stage = cls(ctx, fmt or cls.default_format, msaa)
        self.stage.resize(size)
        self.target = create_target(ctx, size, self.stage.format)
        self.timer = PassTimer(ctx, frames=TIMER_SLOTS)
        self.t = 0.0

    def record(self, encoder, target, t: float) -> None:
        self.stage.record(encoder, target, t)

    def frame(self, readback: bool = False) -> tuple[float, float | None]:
        """(cpu_ms of record + submit, None: GPU times come from collect_gpu); waits for the GPU."""
        cpu_ms, gpu = timed_frame(self.ctx, self.record, self.target, self.timer, self.name, self.t, readback)
        return cpu_ms, gpu_total(gpu)

    def collect_gpu(self) -> list[float | None]:
        """GPU ms of every frame since the last call, oldest first."""
        return [gpu_total(g) for g in self.timer.collect()]


# -- the family ----------------------------------------------------------------------------------


def common_stages() -> list[str]:
    """Stages both paths render, in course order."""
    from wgpurender.raw_path import reference_stage_names
    from wgpurender.wgpu_path.stages import all_stages

    raw = set(reference_stage_names())
    return [name for name in all_stages() if name in raw]


def bench_stage(ctx: GPUContext, name: str, size: tuple[int, int], frames: int, readback_frames: int,
                raw: bool = True) -> list[Result]:
    """One stage at one size on both paths (raw only when it has the stage and ``raw``), interleaved."""
    runner = WgpuStageRunner(ctx, name, size)
    if not raw:
        return measure(runner, frames, readback_frames=readback_frames).results("frames", name, "wgpu", size)
    with RawStageRunner(name, size) as raw_runner:
        samples = measure_interleaved({"wgpu": runner, "raw": raw_runner}, frames, readback_frames)
    return [r for path, s in samples.items() for r in s.results("frames", name, path, size)]
