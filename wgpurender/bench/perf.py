"""``wgpurender bench perf``: every performance family in one run, written as CSV, markdown and plots.

:func:`run_perf` measures, :func:`write_reports` writes ``results.csv``, ``report.md``
and ``perf_*.png`` (plots only when matplotlib is installed: ``pip install .[bench]``).
``--quick`` keeps every family but shrinks sizes, counts and repeats so the whole
run takes well under a minute on lavapipe: it checks the harness, not the numbers.
"""

from __future__ import annotations

import datetime
import os
import platform
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from wgpurender.bench.markdown_scale import CONTROL, TAIL_FAMILIES
from wgpurender.bench.report import NOT_OFFERED, Result, command_line, not_offered, size_text  # noqa: F401 (command_line: the CLI's import)
from wgpurender.core.errors import UserError
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.wgpu_path.device.context import GPUContext, get_context

FAMILIES = ("frames", "scene", "post", "msaa-post", "objects", "scene-scale", CONTROL, "startup")
FULL_SIZES = ((800, 600), (1280, 720), (1920, 1080))
BIG_SIZE = (3840, 2160)
QUICK_SIZES = ((96, 64),)
POST_SIZE = (1280, 720)
FULL_COUNTS = (1_000, 10_000, 100_000)
GPU_COUNTS = (1_000, 10_000, 100_000, 1_000_000, 10_000_000)  # on a GPU adapter
# The largest count per objects mode on a GPU: one call per object (dynamic, immediates) or per recorded draw
# (bundle) is seconds per frame past 100k, and the CPU-animated instancing baseline regenerates and uploads
# 32 bytes an object per frame (10M: ~1.6 s of numpy and 320 MB a frame): it stops at 1M.
GPU_MODE_LIMITS = {"dynamic": 100_000, "immediates": 100_000, "bundle": 100_000, "instancing": 1_000_000}
QUICK_COUNTS = (50, 200)
CPU_PER_DRAW_LIMIT = 10_000  # lavapipe: one call per object at 100k is minutes of run time, for no insight
SCENE_FILE = Path("assets/scenes/final.toml")
# final.toml's chain without FXAA: the scene the raw-Vulkan path draws too (its subpass takes per-pixel effects)
SUBPASS_SCENE_FILE = Path("assets/scenes/final_subpass.toml")
TUTORIAL_SCENES = {"chapter 28": Path("assets/scenes/vulkan_tutorial_28.toml"),
                   "chapter 30": Path("assets/scenes/vulkan_tutorial_30.toml")}
TUTORIAL_SIZE = (800, 600)  # the size of the C++ numbers
STARTUP_STAGE = "3d"
TAIL_FRAMES = 100  # a p99 over 100 samples lets one frame in a hundred stall, as a 99th percentile means



@dataclass
class PerfConfig:
    quick: bool = False
    out_dir: Path = Path("bench-results")
    families: tuple[str, ...] = FAMILIES
    big: bool | None = None  # 3840x2160 too; None: when the adapter is not a CPU
    raw: bool = True  # also run the raw-Vulkan peer
    frames: int | None = None  # timed frames per case (default: timed_frames)
    scene_file: Path = SCENE_FILE
    command: str = ""
    anisotropy: str = DEFAULT_ANISOTROPY  # the scene families' rule (core/plan/anisotropy.py), as render's --anisotropy
    counts: tuple[int, ...] | None = None  # scene-scale's counts (--counts); None: bench/scale.py's (quick: its few)

    def timed_frames(self, ctx: GPUContext | None = None, family: str = "") -> int:
        """--frames, else 4 (quick), else :data:`TAIL_FRAMES` in the families whose p99 is judged on a GPU adapter
        (markdown_scale.TAIL_FAMILIES: the p99 of 20 samples is their largest, a single stall) and in the control
        family, sampled as they are, else 20."""
        if self.frames or self.quick:
            return self.frames or 4
        if family in (*TAIL_FAMILIES, CONTROL) and ctx is not None and ctx.adapter.info["adapter_type"] != "CPU":
            return TAIL_FRAMES
        return 20

    def sizes(self, ctx: GPUContext) -> list[tuple[int, int]]:
        if self.quick:
            return list(QUICK_SIZES)
        big = self.big if self.big is not None else ctx.adapter.info["adapter_type"] != "CPU"
        return [*FULL_SIZES, BIG_SIZE] if big else list(FULL_SIZES)


@dataclass
class PerfRun:
    config: PerfConfig
    machine: dict[str, str]
    results: list[Result] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    seconds: float = 0.0


def machine_info(ctx: GPUContext) -> dict[str, str]:
    import wgpu

    from wgpurender.wgpu_path.binding import name as binding_name

    info = {
        "adapter": ctx.describe(),
        "cpu cores": str(os.cpu_count()),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "wgpu-py": wgpu.__version__,
        "binding": binding_name(),
        "date": datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
    }
    try:
        from wgpurender.raw_path.device.context import get_vulkan

        info["raw Vulkan device"] = get_vulkan().describe()
    except Exception as err:  # the raw path is a peer, not a requirement
        info["raw Vulkan device"] = f"unavailable ({err})"
    return info


def run_perf(config: PerfConfig, ctx: GPUContext | None = None, log: Callable[[str], None] = print) -> PerfRun:
    ctx = ctx or get_context()
    start = time.perf_counter()
    run = PerfRun(config, machine_info(ctx))
    steps = {"frames": _frames, "scene": _scene, "post": _post, "msaa-post": _msaa_post, "objects": _objects,
             "scene-scale": _scene_scale, CONTROL: _control, "startup": _startup}
    for family in config.families:
        log(f"[{family}]")
        steps[family](ctx, config, run, log)
    tails = [f for f in config.families if config.timed_frames(ctx, f) != config.timed_frames()]
    if tails:
        run.notes.append(f"{', '.join(tails)}: {TAIL_FRAMES} timed frames per case (their p99 is judged; the p99 of "
                         f"{config.timed_frames()} samples would be their largest)")
    run.seconds = time.perf_counter() - start
    return run


# -- families -----------------------------------------------------------------------------------


class Progress:
    """A progress line per finished case: '[k/n] what, elapsed, ETA' (the ETA from the mean case so far)."""

    def __init__(self, total: int, log: Callable[[str], None]) -> None:
        self.total, self.log, self.done, self.start = max(1, total), log, 0, time.perf_counter()

    def step(self, what: str) -> None:
        self.done += 1
        elapsed = time.perf_counter() - self.start
        eta = elapsed / self.done * (self.total - self.done)
        self.log(f"  [{self.done}/{self.total}] {what}  ({elapsed:.0f} s elapsed, ETA {eta:.0f} s)")


def _frames(ctx: GPUContext, config: PerfConfig, run: PerfRun, log) -> None:
    from wgpurender.bench.frames import bench_stage, common_stages

    n = config.timed_frames(ctx, "frames")
    cases = [(size, name) for size in config.sizes(ctx) for name in common_stages()]
    progress = Progress(len(cases), log)
    for size, name in cases:
        try:
            run.results += bench_stage(ctx, name, size, n, readback_frames=max(3, n // 2), raw=config.raw)
        except UserError as err:  # this binding cannot draw the stage (Dawn has no clear-texture): a row says so
            run.results.append(not_offered("frames", name, size_text(size), str(err)))
            log(f"  frames: {name} {size[0]}x{size[1]} not offered by this binding: {err}")
        progress.step(f"frames: {name} {size[0]}x{size[1]}")
    skipped = sorted({f"{r.case} ({r.note})" for r in run.results if r.family == "frames" and r.metric == NOT_OFFERED})
    if skipped:
        run.notes.append("frames: not offered by this binding (rows with metric 'not offered'): " + "; ".join(skipped))
    run.notes.append("frames: wgpu-only stages (no raw counterpart) are left out: "
                     + ", ".join(_wgpu_only_stages()) + ".")


def _wgpu_only_stages() -> list[str]:
    from wgpurender.bench.frames import common_stages
    from wgpurender.wgpu_path.stages import all_stages

    common = set(common_stages())
    return [name for name in all_stages() if name not in common] or ["none"]


def _scene(ctx: GPUContext, config: PerfConfig, run: PerfRun, log) -> None:
    from wgpurender.bench.scene import bench_scene

    n = config.timed_frames(ctx, "scene")
    files = list(dict.fromkeys((config.scene_file, SUBPASS_SCENE_FILE)))
    progress = Progress(len(files) * len(config.sizes(ctx)), log)
    for scene_file in files:
        for size in config.sizes(ctx):
            results, note = bench_scene(ctx, scene_file, size, n, raw=config.raw, anisotropy=config.anisotropy)
            run.results += results
            if note and f"scene: {note}" not in run.notes:
                run.notes.append(f"scene: {note}")
                log(f"  scene: {note}")
            if not results:
                break
            progress.step(f"scene: {scene_file.name} {size[0]}x{size[1]}")
    size = QUICK_SIZES[0] if config.quick else TUTORIAL_SIZE
    anchors = Path("../shared/anchors/vulkan-tutorial")
    if not anchors.is_dir():
        run.notes.append(f"tutorial scenes skipped: {anchors} (the C++ tutorial's model and texture) is absent")
        return
    for chapter, path in TUTORIAL_SCENES.items():
        results, note = bench_scene(ctx, path, size, n, raw=False, anisotropy=config.anisotropy)
        run.results += results
        if note:
            run.notes.append(f"scene {chapter}: {note}")
        log(f"  scene: tutorial {chapter}")


def _post(ctx: GPUContext, config: PerfConfig, run: PerfRun, log) -> None:
    from wgpurender.bench.post import bench_effects, bench_probes

    size = QUICK_SIZES[0] if config.quick else POST_SIZE
    n = config.timed_frames()
    run.results += bench_effects(ctx, size, n)
    log("  post: effects")
    run.results += bench_probes(ctx, size, n)
    log("  post: probes")


def _msaa_post(ctx: GPUContext, config: PerfConfig, run: PerfRun, log) -> None:
    """The msaa-post stage on both paths (input-attachment subpass vs a second render pass), every size."""
    from wgpurender.bench.post import bench_msaa_post

    for s in config.sizes(ctx):
        run.results += bench_msaa_post(ctx, s, config.timed_frames(), raw=config.raw)
        log(f"  msaa-post: {s[0]}x{s[1]}")


def _objects(ctx: GPUContext, config: PerfConfig, run: PerfRun, log) -> None:
    from wgpurender.bench.objects import MODES, bench_objects
    from wgpurender.bench.objects_gpu import MODE as GPU_MODE
    from wgpurender.bench.objects_gpu import SPLAT_MODE

    cpu = ctx.adapter.info["adapter_type"] == "CPU"
    counts = QUICK_COUNTS if config.quick else FULL_COUNTS if cpu else GPU_COUNTS
    limit = CPU_PER_DRAW_LIMIT if cpu else None
    modes = [*MODES, GPU_MODE, SPLAT_MODE]
    run.results += bench_objects(ctx, list(counts), modes, config.timed_frames(), per_draw_limit=limit,
                                 log=log, limits=None if cpu else GPU_MODE_LIMITS)
    if not cpu and not config.quick:
        run.notes.append("objects: on a GPU the counts go to 10M for gpu-animated; the per-draw modes and the bundle "
                         "stop at 100k, the CPU-animated instancing baseline at 1M (10M would be ~1.6 s of numpy "
                         "and a 320 MB upload per frame).")
    if cpu and max(counts) > CPU_PER_DRAW_LIMIT:
        run.notes.append(f"objects: on a CPU adapter the per-draw modes (dynamic, immediates) stop at "
                         f"{CPU_PER_DRAW_LIMIT} objects; 100k runs instancing and the bundle only.")
    if not ctx.has("immediates"):
        run.notes.append("objects: the adapter lacks 'immediates', that mode was skipped.")


def _scene_scale(ctx: GPUContext, config: PerfConfig, run: PerfRun, log) -> None:
    """N instanced copies and N distinct meshes of a lit, textured cube; pygfx beside (bench/scale.py)."""
    from wgpurender.bench.scale import COUNTS, QUICK_COUNTS, bench_scale, ratio_rows
    from wgpurender.bench.scale_paired import bench_paired
    from wgpurender.bench.scale_pygfx import pygfx_pair, pygfx_peer

    counts = config.counts or (QUICK_COUNTS if config.quick else COUNTS)
    size = QUICK_SIZES[0] if config.quick else (800, 600)
    results, notes = bench_scale(ctx, list(counts), config.timed_frames(ctx, "scene-scale"), size, log,
                                 pygfx_peer())
    paired, paired_notes = bench_paired(ctx, list(counts), size, pygfx_pair(), log=log)
    run.results += results + ratio_rows(results) + paired
    run.notes += notes + paired_notes


def _control(ctx: GPUContext, config: PerfConfig, run: PerfRun, log) -> None:
    """The host's own tail: a fixed CPU workload and an empty GPU round trip, sampled as the frame rows are."""
    from wgpurender.bench.control import bench_control

    run.results += bench_control(ctx, config.timed_frames(ctx, CONTROL))
    log("  control: cpu-fixed, gpu-empty")


def _startup(ctx: GPUContext, config: PerfConfig, run: PerfRun, log) -> None:
    from wgpurender.bench.startup import ROUNDS, bench_startup

    size = QUICK_SIZES[0] if config.quick else (800, 600)
    run.results += bench_startup(STARTUP_STAGE, size, 2 if config.quick else ROUNDS, quick=config.quick,
                                 raw=config.raw, log=log)
    run.notes.append("startup: wgpu-py 0.32 cannot create a pipeline cache (the device feature 'pipeline-cache' "
                     "is offered, but neither wgpu-native's C header nor wgpu-py has a function to make one); the "
                     "wgpu rows are without one. The raw path's VkPipelineCache is compared absent vs present.")


# -- reports --------------------------------------------------------------------------------------


def write_reports(run: PerfRun, out_dir: Path | None = None, docs_img: Path | None = None) -> dict[str, Path]:
    """results.csv, report.md and (with matplotlib) perf_*.png in ``out_dir``; plots also copied to ``docs_img``."""
    from wgpurender.bench.markdown import render_markdown
    from wgpurender.bench.plots import write_plots
    from wgpurender.bench.report import have_matplotlib, write_csv

    out_dir = Path(out_dir or run.config.out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = {"csv": write_csv(run.results, out_dir / "results.csv")}
    plots: dict[str, Path] = {}
    if have_matplotlib():
        plots = write_plots(run.results, out_dir)
        if docs_img is not None:
            import shutil

            Path(docs_img).mkdir(parents=True, exist_ok=True)
            for p in plots.values():
                shutil.copy(p, Path(docs_img) / p.name)
    else:
        run.notes.append("plots: matplotlib is not installed (pip install 'wgpurender[bench]'); no PNGs written.")
    report = out_dir / "report.md"
    report.write_text(render_markdown(run, {k: p.name for k, p in plots.items()}))
    paths["markdown"] = report
    paths.update({f"plot_{k}": p for k, p in plots.items()})
    return paths

