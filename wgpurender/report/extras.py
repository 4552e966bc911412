"""The report's closing sections, measured while the report is built: accuracy against cost, and the hard cases.

- **Accuracy**: the accuracy suite (wgpurender/bench/accuracy_run.py) in a quick variant: every quality
  knob of ``final.toml`` swept one at a time at a small size, a few frames each, scored with FLIP against
  the 8x-supersampled ground truth and timed with GPU timestamps; the Pareto plot is drawn from this run.
- **Hard cases**: the analytic suite (wgpurender/bench/accuracy_analytic.py): slivers and sub-pixel
  triangles against their exact coverage, a plane at a grazing angle against the float64 filter integral,
  the depth-stress scene against its known image.

Nothing is copied from docs/: docs/accuracy.md and docs/numerics.md hold the full runs (and the hard cases
that need the test suite's float64 references), and the page links to them.
"""

from __future__ import annotations

import datetime
import math
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from wgpurender.core.files.assets import scene_dir
from wgpurender.wgpu_path.device.context import GPUContext

SCENE = scene_dir() / "final.toml"
SIZE = (128, 96)  # small: the ground truth renders 8x it
FRAMES, WARMUP = 2, 1
PLOT = "accuracy_pareto.png"
# The shimmer cases, small and few (a report build runs in CI on 2 cores): the settings whose order teaches.
SHIMMER_SIZE, SHIMMER_FRAMES = (64, 48), 4
SHIMMER_EDGES, SHIMMER_PLANE = ("none", "msaa4"), ("nearest", "linear", "trilinear")


@dataclass(frozen=True)
class Point:
    """One measured setting: what was set, its error and its time."""

    group: str  # the knob swept (accuracy), or the hard case's section
    setting: str
    flip: float
    psnr: float
    ms: float  # GPU time per frame when timestamps exist, else wall time (median)
    pareto: bool = False


@dataclass
class Measured:
    size: tuple[int, int]
    adapter: str
    when: str
    seconds: float = 0.0
    accuracy: list[Point] = field(default_factory=list)
    hard_cases: list[Point] = field(default_factory=list)
    plot: str | None = None  # the plot's file name in the site; None without matplotlib
    timer: str = "GPU"
    shimmer: list = field(default_factory=list)  # bench/accuracy_shimmer.ShimmerRow
    shimmer_size: tuple[int, int] = SHIMMER_SIZE
    shimmer_frames: int = SHIMMER_FRAMES


def measure(ctx: GPUContext, site: Path, log: Callable[[str], None] = print, size: tuple[int, int] = SIZE
            ) -> Measured:
    """Run both suites' quick variants on ``ctx``; the plot goes into ``site``."""
    import time

    from wgpurender.bench.accuracy_analytic import run_analytic
    from wgpurender.bench.accuracy_report import write_plot
    from wgpurender.bench.accuracy_run import AccuracyConfig, run_accuracy, unique_rows
    from wgpurender.bench.report import have_matplotlib

    start = time.perf_counter()
    when = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    out = Measured(size, ctx.describe(), when)
    with tempfile.TemporaryDirectory(prefix="wgpurender-report-accuracy-") as work:
        log(f"accuracy: every knob of {SCENE.name} at {size[0]}x{size[1]}, {FRAMES} frames each")
        config = AccuracyConfig(scene_path=SCENE, base_size=size, frames=FRAMES, warmup=WARMUP, rounds=1,
                                combinations=False, out_dir=Path(work), command="wgpurender report")
        run = run_accuracy(config, ctx, progress_stream=sys.stdout)  # beside the report's other progress lines
        rows = unique_rows([r for r in run.rows if r.case.scene == "final" and r.case.sweep != "ground truth"])
        out.timer = "GPU" if all(r.m.gpu is not None for r in rows) else "wall"
        out.accuracy = [Point(r.case.sweep, r.case.level, r.flip, r.psnr, r.time_ms, r.pareto) for r in rows]
        if have_matplotlib():
            write_plot(run, site / PLOT)
            out.plot = PLOT
        log("hard cases: anti-aliasing, texture filtering and depth against exact answers")
        truth = run_analytic(ctx, Path(work), size, FRAMES, WARMUP, progress=lambda _text: None, ibl=False)
        out.hard_cases = [Point(r.section, r.setting, r.flip, r.psnr,
                                r.m.gpu.median if r.m.gpu is not None else r.m.wall.median) for r in truth]
        log("shimmer: edges and a minified plane under slow motion against their moving truths")
        from wgpurender.bench.accuracy_shimmer import run_shimmer

        out.shimmer = run_shimmer(ctx, Path(work), SHIMMER_SIZE, SHIMMER_FRAMES, lambda _text: None,
                                  SHIMMER_EDGES, SHIMMER_PLANE)
    out.seconds = time.perf_counter() - start
    return out


def number(value: float, digits: int) -> str:
    if math.isnan(value):
        return "n/a"
    return "inf" if math.isinf(value) else f"{value:.{digits}f}"
