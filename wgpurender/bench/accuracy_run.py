"""The accuracy sweep: which settings are rendered, how each is timed, and its error against the ground truth.

Every knob is swept one at a time from :data:`~.accuracy_knobs.TOP` (all knobs at their highest level, 1x),
so each row differs from the ground truth (TOP at 8x supersampling) in one knob plus the supersampling factor;
a few combinations follow (MSAA x supersampling, trilinear x supersampling, everything lowest), then the
depth knob on the depth-stress scene, whose ground truth is analytic (accuracy_depth.py).

A setting used by several sweeps (TOP is in all of them) is rendered and timed once.
Time per frame: ``warmup`` untimed frames, then ``frames`` timed ones, split over ``rounds`` passes through all
settings (each later visit starts with one untimed frame), so a change in the machine's load during the run
spreads over every setting instead of landing on a few; a frame is record + submit + wait (no readback, no CPU
downsampling). GPU time is the sum of the frame's passes from timestamp queries
(:class:`~wgpurender.wgpu_path.device.timing.PassTimer`); wall time is measured around the whole
frame. Both: median, p10..p90.
"""

from __future__ import annotations

import functools
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wgpurender.bench.accuracy_depth import analytic_image, write_depth_scene
from wgpurender.bench.accuracy_downsample import downsample_srgb8
from wgpurender.bench.accuracy_floor import EMPTY_SCENE, Floor
from wgpurender.bench.accuracy_knobs import (
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
from wgpurender.core.verdict.compare import compare_images
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.device.timing import PassTimer, Stats

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
    below_floor: bool = False  # its time is under the run's noise floor (accuracy_floor.py)

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


class Timed:
    """One setting's renderer and target, and the frame times gathered for it over the rounds."""

    def __init__(self, ctx: GPUContext, scene, settings: Settings, base_size: tuple[int, int], knobs) -> None:

        self.ctx, self.settings = ctx, settings
        self.renderer = make_renderer(ctx, scene, settings, base_size, knobs=knobs)
        self.target = self.renderer.create_output()
        self.timer = PassTimer(ctx)
        self.wall: list[float] = []
        self.gpu: list[float] = []
        self.passes: dict[str, list[float]] = {}
        self.pixels: np.ndarray | None = None

    def frame(self) -> tuple[float, dict[str, float]]:
        """Record, submit and wait for one frame: (wall ms, GPU ms per pass)."""
        timer = self.timer
        f = run_frame(self.ctx, functools.partial(self.renderer.record, timer=timer), self.target, 0.0,
                      label="accuracy-frame", read_back=False, timer=timer)  # the timer read waits for the GPU
        return f.frame_ms, f.gpu_ms

    def run(self, frames: int, warmup: int = 0) -> None:
        for i in range(warmup + frames):
            ms, per_pass = self.frame()
            if i < warmup:
                continue
            self.wall.append(ms)
            if per_pass:
                self.gpu.append(sum(per_pass.values()))
                for label, v in per_pass.items():
                    self.passes.setdefault(label, []).append(v)

    def read(self) -> None:
        """Read the image back (once: it is the same every frame) and resolve it to the base size."""
        from wgpurender.wgpu_path.device.targets import read_texture

        pixels = read_texture(self.ctx, self.target)
        if pixels.dtype != np.uint8:
            raise ValueError(f"accuracy needs an 8-bit sRGB output, got {self.renderer.plan.output_format}")
        self.pixels = downsample_srgb8(pixels, self.settings.ss)

    def measurement(self) -> Measurement:
        medians = {label: float(np.median(v)) for label, v in self.passes.items()}
        return Measurement(self.pixels, self.renderer.plan.size, Stats.of(self.wall),
                           Stats.of(self.gpu) if self.gpu else None, medians)


@dataclass
class AccuracyConfig:
    scene_path: Path
    base_size: tuple[int, int]
    frames: int
    warmup: int
    rounds: int = 1  # the timed frames are split over this many passes through all settings (drift evens out)
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
    floor: Floor | None = None


def run_accuracy(config: AccuracyConfig, ctx: GPUContext, progress_stream=None) -> AccuracyRun:
    """Render, time and score every case of :func:`plan_cases`."""
    from wgpurender.bench.accuracy_pareto import pareto_front
    from wgpurender.core.scene import load_scene

    start = time.perf_counter()
    cases = plan_cases(config.knobs, config.combinations)
    scenes = {FINAL: load_scene(config.scene_path)}
    if any(c.scene == DEPTH_STRESS for c in cases):
        scenes[DEPTH_STRESS] = load_scene(write_depth_scene(config.out_dir / "depth_stress", config.base_size))
    scene_knobs = {FINAL: KNOBS, DEPTH_STRESS: ("depth",)}
    unique = list(dict.fromkeys(c.key for c in cases))
    rounds = max(1, min(config.rounds, config.frames))
    per_round = [config.frames // rounds + (1 if r < config.frames % rounds else 0) for r in range(rounds)]
    progress = Progress(len(unique) * rounds, progress_stream)
    timed: dict[tuple[str, Settings], Timed] = {}
    for r, frames in enumerate(per_round):
        # Alternate the order, so a setting is not always timed right after the same neighbour.
        for key in (unique if r % 2 == 0 else unique[::-1]):
            scene_name, settings = key
            first = key not in timed
            if first:
                timed[key] = Timed(ctx, scenes[scene_name], settings, config.base_size, scene_knobs[scene_name])
            t = timed[key]
            t.run(frames, warmup=config.warmup if first else 1)
            if first:
                t.read()
            what = settings.label() if scene_name == FINAL else settings.depth
            took = float(np.median(t.gpu[-frames:] if t.gpu else t.wall[-frames:]))
            size = t.renderer.plan.size
            progress.step(f"round {r + 1}/{rounds} {scene_name}: {what} at {size[0]}x{size[1]}: {took:.1f} ms")
    measured = {key: t.measurement() for key, t in timed.items()}
    rows = [score(c, measured, config.base_size) for c in cases]
    floor = noise_floor(ctx, config.frames)
    for r in rows:
        r.below_floor = floor.below(r.m.gpu.median if r.m.gpu else None, r.m.wall.median)
    final_rows = unique_rows([r for r in rows if r.case.scene == FINAL and r.case.sweep != "ground truth"])
    for i in pareto_front([(r.time_ms, r.flip) for r in final_rows]):
        for r in rows:
            if r.case.key == final_rows[i].case.key:
                r.pareto = True
    return AccuracyRun(config, ctx.describe(), rows, time.perf_counter() - start, floor=floor)


def noise_floor(ctx: GPUContext, frames: int) -> Floor:
    """The run's noise floor (accuracy_floor.py), its empty scene in a temporary folder (nothing left in --out)."""
    import tempfile

    from wgpurender.core.scene import load_scene

    with tempfile.TemporaryDirectory(prefix="wgpurender-floor-") as work:
        path = Path(work) / "empty.toml"
        path.write_text(EMPTY_SCENE)
        t = Timed(ctx, load_scene(path), Settings(msaa=1), (8, 8), ())
    t.run(max(frames, 3), warmup=1)
    m = t.measurement()
    return Floor(m.gpu.median if m.gpu else None, m.wall.median)


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
    from wgpurender.bench.accuracy_depth import wrong_pixels

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
