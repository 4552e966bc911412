"""Issue 31's goal row: wgpu's ``instanced/N`` against pygfx's ``InstancedMesh``, paired round by round.

The sequential row (bench/scale.py's :func:`~wgpurender.bench.scale.ratio_rows`) divides two medians measured one
after the other in the process. On the H100, whose SM clock is not locked, the same draw read 0.273 ms in bench
perf's row and 1.564 ms interleaved in one process (docs/perf-h100/2026-11-27-late/scale): a 5.7x that is the
clock's, not the renderer's. Here both sides are alive together (bench/frames.py's ``measure_interleaved`` and
benchmarks/post_interleave.py's rounds do the same): each round reads the SM clock, then each side draws one
untimed frame and :data:`FRAMES` timed ones with the image read back (pygfx's offscreen canvas offers no other
frame), the order flipping each round; the round's ratio is wgpu's median over pygfx's. The goal is judged on the
median of the rounds' ratios (:data:`PAIRED`), with its p10/p90, each side's median and the clock's range.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from wgpurender.bench.frames import frames_without_gc, settle_garbage, warm_up
from wgpurender.bench.report import Result, size_text
from wgpurender.bench.scale import PYGFX_LIMIT, instanced_scene
from wgpurender.bench.sm_clock import NO_CLOCK, clock_span, sm_clock
from wgpurender.wgpu_path.device.timing import Stats

PAIRED = "frame_ratio:paired"  # the goal's row: the median of the rounds' ratios
PAIRED_FRAME = "frame_readback_ms:paired"  # each side's frame with readback, the median of its round medians
CLOCK = "sm_clock_mhz"  # the SM clock read before each round: median, min (p10 column), max (p90 column)
ROUNDS, FRAMES = 10, 5
SIDES = ("wgpu", "pygfx")


@dataclass
class Round:
    """One round: which side drew first, the SM clock read before it, each side's median frame (ms)."""

    first: str
    clock: str
    ms: dict[str, float]

    @property
    def ratio(self) -> float:
        return self.ms["wgpu"] / self.ms["pygfx"]


def paired_rounds(sides: dict[str, Callable[[], object]], rounds: int = ROUNDS, frames: int = FRAMES,
                  timer: Callable[[], float] = time.perf_counter,
                  clock: Callable[[], str] = sm_clock) -> list[Round]:
    """``rounds`` rounds over ``sides`` (name -> draw one frame and wait for it), the first side first in even
    rounds and last in odd ones; the clock is read at each round's start, before either side draws."""
    names = list(sides)
    out = []
    with frames_without_gc():
        for k in range(rounds):
            order = names if k % 2 == 0 else names[::-1]
            reading = clock()
            ms = {name: _median_frame(sides[name], frames, timer) for name in order}
            out.append(Round(order[0], reading, ms))
    return out


def _median_frame(draw: Callable[[], object], frames: int, timer: Callable[[], float]) -> float:
    """One untimed frame (the first after the other side's), then the median of ``frames`` timed ones (ms)."""
    draw()
    times = []
    for _ in range(frames):
        start = timer()
        draw()
        times.append((timer() - start) * 1e3)
    return statistics.median(times)


def paired_rows(rounds: list[Round], n: int, size: tuple[int, int], frames: int = FRAMES) -> list[Result]:
    """The goal's row (ratio/N, :data:`PAIRED`), each side's :data:`PAIRED_FRAME` row and the :data:`CLOCK` row."""
    s, span = size_text(size), clock_span([r.clock for r in rounds])
    how = (f"{len(rounds)} rounds, {frames} frames with readback a side each, the order flipped each round; "
           f"{span}")
    out = [Result.of("scene-scale", f"ratio/{n}", "wgpu/pygfx", s, PAIRED, Stats.of([r.ratio for r in rounds]),
                     f"median of the rounds' ratios, wgpu instanced / pygfx InstancedMesh (goal <= 0.5): {how}")]
    for side, case in zip(SIDES, (f"instanced/{n}", f"pygfx/{n}"), strict=True):
        out.append(Result.of("scene-scale", case, side, s, PAIRED_FRAME, Stats.of([r.ms[side] for r in rounds]),
                             f"the rounds' medians, paired with the other side: {how}"))
    mhz = [int(r.clock) for r in rounds if r.clock.isdigit()]
    if mhz:
        out.append(Result("scene-scale", f"ratio/{n}", "wgpu/pygfx", s, CLOCK, statistics.median(mhz), min(mhz),
                          max(mhz), len(mhz), "SM clock before each round: median, min (p10), max (p90)"))
    else:
        nan = float("nan")
        out.append(Result("scene-scale", f"ratio/{n}", "wgpu/pygfx", s, CLOCK, nan, nan, nan, 0, NO_CLOCK))
    return out


class _Draw:
    """bench/frames.warm_up's runner protocol over a draw function."""

    def __init__(self, draw: Callable[[], object]) -> None:
        self.draw = draw

    def frame(self, readback: bool = False) -> None:
        self.draw()


def bench_paired(ctx, counts: list[int], size: tuple[int, int], pygfx_side, rounds: int = ROUNDS,
                 frames: int = FRAMES, log: Callable[[str], None] = print) -> tuple[list[Result], list[str]]:
    """(rows, notes) of the paired family at each count up to :data:`PYGFX_LIMIT`; ``pygfx_side(ctx, n, size)``
    gives pygfx's draw function (bench/scale_pygfx.py's), or is None when pygfx is not installed: then nothing
    (bench/scale.py's bench_scale already says so in one line)."""
    if pygfx_side is None:
        return [], []
    from wgpurender.bench.scene import SceneRunner

    gpu = ctx.adapter.info["adapter_type"] != "CPU"
    out: list[Result] = []
    with tempfile.TemporaryDirectory(prefix="wgpurender-paired-") as tmp:
        for n in [n for n in counts if n <= PYGFX_LIMIT]:
            runner = SceneRunner(ctx, instanced_scene(Path(tmp), n, size), size)
            sides = {"wgpu": lambda r=runner: r.frame(readback=True), "pygfx": pygfx_side(ctx, n, size)}
            settle_garbage()
            for draw in sides.values():
                warm_up(_Draw(draw))
            runner.collect_gpu()  # its timestamps are not read: keep the timer's slots free
            got = paired_rounds(sides, rounds, frames, clock=sm_clock if gpu else lambda: "?")
            runner.collect_gpu()
            out += paired_rows(got, n, size, frames)
            log(f"  scene-scale: paired wgpu/pygfx {n}")
    return out, [f"scene-scale: the goal's ratio is paired ({PAIRED}): wgpu instanced and pygfx alive together, "
                 f"{rounds} rounds of {frames} readback frames a side, the order flipped each round, the SM clock "
                 "read before each; frame_ratio beside it is the ratio of two medians measured one after the other"]
