"""The accuracy sweep: which settings are rendered, how each is timed, and its error against the ground truth.

Every knob is swept one at a time from :data:`~.accuracy_knobs.TOP` (all knobs at their highest level, 1x),
so each row differs from the ground truth (TOP at 8x supersampling) in one knob plus the supersampling factor;
a few combinations follow (MSAA x supersampling, trilinear x supersampling, everything lowest), then the
depth knob on the depth-stress scene, whose ground truth is analytic (accuracy_depth.py).

A setting used by several sweeps (TOP is in all of them) is rendered and timed once.
Time per frame: ``warmup`` untimed frames, then ``frames`` timed ones; a frame is record + submit + wait (no
readback, no CPU downsampling). GPU time is the sum of the frame's passes from timestamp queries
(:class:`~wgpurender.timing.PassTimer`); wall time is measured around the whole frame. Both: median, p10..p90.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..compare import compare_images
from ..gpu import GPUContext
from ..timing import PassTimer, Stats
from .accuracy_depth import analytic_image, write_depth_scene
from .accuracy_downsample import downsample_srgb8
from .accuracy_knobs import (
    DEPTH_LEVELS,
    FILTER_LEVELS,
    FORMAT_LEVELS,
    GROUND_TRUTH,
    KNOBS,
    MSAA_LEVELS,
    SS_LEVELS,
    TOP,
    Settings,
    make_renderer,
)

FINAL, DEPTH_STRESS = "final", "depth-stress"
LOWEST = {"msaa": MSAA_LEVELS[0], "ss": SS_LEVELS[0], "format": FORMAT_LEVELS[0], "filter": FILTER_LEVELS[0],
          "depth": DEPTH_LEVELS[0]}


@dataclass(frozen=True)
class Case:
    """One row of the sweep: ``sweep`` (a knob, a combination, or "ground truth"), its level, the setting."""

    sweep: str
    level: str
    settings: Settings
    scene: str = FINAL
    isolated_ref: Settings | None = None  # the same setting with the swept knob at its top (None: combinations)
    note: str = ""

    @property
    def key(self) -> tuple[str, Settings]:
        return self.scene, self.settings


def plan_cases(knobs: tuple[str, ...] = KNOBS, combinations: bool = True) -> list[Case]:
    """The rows, in report order. ``knobs``: which knobs to sweep (the others stay at TOP)."""
    cases = [Case("ground truth", f"ss{GROUND_TRUTH.ss}", GROUND_TRUTH, note="reference of the final-scene rows")]
    one = {
        "msaa": [("msaa", str(m), TOP.with_(msaa=m), TOP) for m in MSAA_LEVELS],
        "ss": [("ss", f"{k}x", TOP.with_(ss=k), GROUND_TRUTH) for k in SS_LEVELS],
        # rgba32float cannot be multisampled, so the whole format sweep runs at msaa 1 to stay comparable.
        "format": [("format", f, TOP.with_(msaa=1, format=f), TOP.with_(msaa=1, format=FORMAT_LEVELS[-1]))
                   for f in FORMAT_LEVELS],
        "filter": [("filter", f, TOP.with_(filter=f), TOP) for f in FILTER_LEVELS],
        "depth": [("depth", d, TOP.with_(depth=d), TOP) for d in DEPTH_LEVELS],
    }
    notes = {"format": "at msaa 1: rgba32float cannot be multisampled"}
    for knob in knobs:
        for sweep, level, settings, ref in one[knob]:
            cases.append(Case(sweep, level, settings, isolated_ref=ref, note=notes.get(knob, "")))
    if combinations:
        if "msaa" in knobs and "ss" in knobs:
            cases += [Case("msaa1 x ss", f"{k}x", TOP.with_(msaa=1, ss=k)) for k in SS_LEVELS]
        if "filter" in knobs and "ss" in knobs:
            cases += [Case("trilinear x ss", f"{k}x", TOP.with_(filter="trilinear", ss=k)) for k in SS_LEVELS[1:]]
        if len(knobs) >= 2:  # the knob names are Settings' field names
            lowest = TOP.with_(**{k: low for k, low in LOWEST.items() if k in knobs})
            cases.append(Case("lowest", "all", lowest, note="every swept knob at its lowest level"))
    if "depth" in knobs:
        cases += [Case(DEPTH_STRESS, d, TOP.with_(depth=d), scene=DEPTH_STRESS, note="analytic ground truth")
                  for d in DEPTH_LEVELS]
    return cases


@dataclass
class Measurement:
    pixels: np.ndarray  # (H, W, 4) uint8 sRGB at the base size (downsampled when supersampled)
    render_size: tuple[int, int]
    wall: Stats
    gpu: Stats | None
    passes: dict[str, float] = field(default_factory=dict)  # median GPU ms per pass label


@dataclass
class Row:
    case: Case
    m: Measurement
    flip: float = float("nan")
    psnr: float = float("nan")
    flip_isolated: float = float("nan")
    psnr_isolated: float = float("nan")
    wrong_pixels: int | None = None
    pareto: bool = False

    @property
    def time_ms(self) -> float:
        """The time the Pareto front and the plot use: GPU time when timestamps exist, else wall time."""
        return self.m.gpu.median if self.m.gpu is not None else self.m.wall.median


class Progress:
    """A line-based progress bar on stderr: one line per finished step, with elapsed time."""

    def __init__(self, total: int, stream=None, width: int = 24) -> None:
        self.total, self.done, self.width = total, 0, width
        self.stream = stream if stream is not None else sys.stderr
        self.start = time.perf_counter()

    def step(self, text: str) -> None:
        self.done += 1
        filled = round(self.width * self.done / max(1, self.total))
        elapsed = time.perf_counter() - self.start
        bar = "#" * filled + "-" * (self.width - filled)
        print(f"[{bar}] {self.done:>3}/{self.total} {100 * self.done / max(1, self.total):3.0f}% "
              f"{int(elapsed) // 60}:{int(elapsed) % 60:02d}  {text}", file=self.stream, flush=True)


def time_frames(ctx: GPUContext, renderer, target, frames: int, warmup: int) -> tuple[Stats, Stats | None, dict]:
    """(wall, gpu, per-pass medians) of ``frames`` frames after ``warmup`` untimed ones."""
    timer = PassTimer(ctx)
    wall, gpu, passes = [], [], {}
    for i in range(warmup + frames):
        start = time.perf_counter()
        timer.reset()
        encoder = ctx.device.create_command_encoder(label="accuracy-frame")
        renderer.draw(encoder, target, 0.0, timer=timer)
        timer.resolve(encoder)
        ctx.queue.submit([encoder.finish()])
        per_pass = timer.read()  # blocks until the frame is done
        if not per_pass:
            ctx.wait_idle()
        ms = (time.perf_counter() - start) * 1e3
        if i >= warmup:
            wall.append(ms)
            if per_pass:
                gpu.append(sum(per_pass.values()))
                for label, v in per_pass.items():
                    passes.setdefault(label, []).append(v)
    medians = {label: float(np.median(v)) for label, v in passes.items()}
    return Stats.of(wall), (Stats.of(gpu) if gpu else None), medians


def measure(ctx: GPUContext, scene, settings: Settings, base_size: tuple[int, int], frames: int, warmup: int,
            knobs=KNOBS) -> Measurement:
    """Render ``settings`` (at ``base_size * ss``), time it, read it back and downsample it to ``base_size``."""
    from ..targets import create_target, read_texture

    renderer = make_renderer(ctx, scene, settings, base_size, knobs=knobs)
    target = create_target(ctx, renderer.plan.size, renderer.plan.output_format)
    wall, gpu, passes = time_frames(ctx, renderer, target, frames, warmup)
    pixels = read_texture(ctx, target)
    if pixels.dtype != np.uint8:
        raise ValueError(f"accuracy needs an 8-bit sRGB output, got {renderer.plan.output_format}")
    return Measurement(downsample_srgb8(pixels, settings.ss), renderer.plan.size, wall, gpu, passes)


@dataclass
class AccuracyConfig:
    scene_path: Path
    base_size: tuple[int, int]
    frames: int
    warmup: int
    knobs: tuple[str, ...] = KNOBS
    combinations: bool = True
    out_dir: Path = Path("bench-results/accuracy")
    command: str = ""


@dataclass
class AccuracyRun:
    config: AccuracyConfig
    adapter: str
    rows: list[Row]
    seconds: float
    notes: list[str] = field(default_factory=list)


def run_accuracy(config: AccuracyConfig, ctx: GPUContext, progress_stream=None) -> AccuracyRun:
    """Render, time and score every case of :func:`plan_cases`."""
    from ..scene import load_scene
    from .accuracy_pareto import pareto_front

    start = time.perf_counter()
    cases = plan_cases(config.knobs, config.combinations)
    scenes = {FINAL: load_scene(config.scene_path)}
    if any(c.scene == DEPTH_STRESS for c in cases):
        scenes[DEPTH_STRESS] = load_scene(write_depth_scene(config.out_dir / "depth_stress", config.base_size))
    scene_knobs = {FINAL: KNOBS, DEPTH_STRESS: ("depth",)}
    unique = list(dict.fromkeys(c.key for c in cases))
    progress = Progress(len(unique), progress_stream)
    measured: dict[tuple[str, Settings], Measurement] = {}
    for scene_name, settings in unique:
        m = measure(ctx, scenes[scene_name], settings, config.base_size, config.frames, config.warmup,
                    knobs=scene_knobs[scene_name])
        measured[(scene_name, settings)] = m
        took = m.gpu.median if m.gpu is not None else m.wall.median
        what = settings.label() if scene_name == FINAL else settings.depth
        progress.step(f"{scene_name}: {what} at {m.render_size[0]}x{m.render_size[1]}: {took:.1f} ms")
    rows = [score(c, measured, config.base_size) for c in cases]
    final_rows = unique_rows([r for r in rows if r.case.scene == FINAL and r.case.sweep != "ground truth"])
    for i in pareto_front([(r.time_ms, r.flip) for r in final_rows]):
        for r in rows:
            if r.case.key == final_rows[i].case.key:
                r.pareto = True
    return AccuracyRun(config, ctx.describe(), rows, time.perf_counter() - start)


def unique_rows(rows: list[Row]) -> list[Row]:
    """The first row of each distinct (scene, setting)."""
    seen, out = set(), []
    for r in rows:
        if r.case.key not in seen:
            seen.add(r.case.key)
            out.append(r)
    return out


def score(case: Case, measured: dict, base_size: tuple[int, int]) -> Row:
    """Errors of a case: against the ground truth (rendered or analytic) and against its knob's top level."""
    from ..numerics.depth_planes import wrong_pixels

    m = measured[case.key]
    if case.scene == DEPTH_STRESS:
        truth = analytic_image(base_size)
    else:
        truth = measured[(FINAL, GROUND_TRUTH)].pixels
    c = compare_images(truth, m.pixels)
    row = Row(case, m, flip=c.flip_mean, psnr=c.psnr)
    if case.scene == DEPTH_STRESS:
        row.wrong_pixels = wrong_pixels(m.pixels)
    elif case.isolated_ref is not None and (case.scene, case.isolated_ref) in measured:
        iso = compare_images(measured[(case.scene, case.isolated_ref)].pixels, m.pixels)
        row.flip_isolated, row.psnr_isolated = iso.flip_mean, iso.psnr
    return row
