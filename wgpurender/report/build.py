"""Build the report site: every step rendered, compared and timed, then the page and its PNGs written at once.

The site is written into a temporary folder beside ``out_dir`` and moved into place when it
is complete, so a failed build leaves the previous report (or nothing), never half a site.
An existing ``out_dir`` is replaced only when it is empty or a previous report.
"""

from __future__ import annotations

import datetime
import shutil
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from wgpurender.core.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.core.assets import scene_dir
from wgpurender.core.errors import UserError
from wgpurender.core.imageio import save_png
from wgpurender.core.safe_write import cleanup_on_signal
from wgpurender.report import extras, page
from wgpurender.report.steps import Step, heatmap_scale, scene_step, stage_step
from wgpurender.wgpu_path.gpu import GPUContext, get_context

REPO_ROOT = Path(__file__).resolve().parents[2]
SCENE_DIR = scene_dir()  # the checkout's assets/scenes, or the wheel's copy
# Scene files in course order: the minimal plan first, the complete scene, then the C++ tutorial's chapters
# (those read the tutorial's model from ../shared/anchors and are left out where it is missing).
SCENES = ("unlit", "retro", "brick", "final_subpass", "final", "vulkan_tutorial_28", "vulkan_tutorial_30")
STAGE_SIZE = (240, 180)
SCENE_SIZE = (240, 180)
# lavapipe's anisotropic filtering is pathological at some sizes (notes/facts.md): brick.toml takes 11 s a frame
# at 320x240 but 0.2 s at 240x180; vulkan_tutorial_28.toml 17 s a frame at 240x180 but 0.5 s at 320x240.
SCENE_SIZES = {"vulkan_tutorial_28": (320, 240), "vulkan_tutorial_30": (320, 240)}


def course_stages() -> list[str]:
    """Stage names of both paths in course order (course/steps.py); a stage only one path has is a step too."""
    from wgpurender.core.course.steps import course_position
    from wgpurender.raw_path.stages import all_ref_stages
    from wgpurender.wgpu_path.stages import all_stages

    return sorted(set(all_stages()) | set(all_ref_stages()), key=course_position)


def check_out_dir(out_dir: Path) -> Path:
    out_dir = Path(out_dir)
    if out_dir.exists():
        if not out_dir.is_dir():
            raise UserError(f"cannot write the report to {out_dir}: it is a file, give a folder")
        index = out_dir / "index.html"
        ours = index.is_file() and page.GENERATOR_MARK in index.read_text(encoding="utf-8", errors="replace")
        if any(out_dir.iterdir()) and not ours:
            raise UserError(f"{out_dir} is not empty and holds no earlier report: give a new or empty folder")
    elif not out_dir.parent.is_dir():
        raise UserError(f"cannot write the report to {out_dir}: folder {out_dir.parent} does not exist")
    return out_dir


def build_report(out_dir: str | Path, *, stages: list[str] | None = None, scenes: list[Path] | None = None,
                 ctx: GPUContext | None = None, log: Callable[[str], None] = print,
                 anisotropy: str = DEFAULT_ANISOTROPY) -> Path:
    """Render every step on both paths and write the site; returns the path of index.html. ``anisotropy``:
    the scenes' rule (core/anisotropy.py), as ``render --anisotropy``."""
    out_dir = check_out_dir(Path(out_dir))
    ctx = ctx or get_context()
    start = time.perf_counter()
    steps: list[Step] = []
    for name in course_stages() if stages is None else stages:
        log(f"stage {name}")
        steps.append(stage_step(ctx, name, STAGE_SIZE, log))
    for path in _scene_files() if scenes is None else scenes:
        log(f"scene {path.name}")
        steps.append(scene_step(ctx, Path(path), SCENE_SIZES.get(Path(path).stem, SCENE_SIZE), log, anisotropy))
    with cleanup_on_signal():  # SIGTERM while the temp folder exists ends through finally
        tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.", dir=out_dir.parent))
        try:
            _write_site(tmp, steps, ctx, time.perf_counter() - start)
            if out_dir.exists():
                shutil.rmtree(out_dir)
            tmp.rename(out_dir)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    log(f"report: {len(steps)} steps in {time.perf_counter() - start:.1f} s")
    return out_dir / "index.html"


def _scene_files() -> list[Path]:
    """The repository's scenes in course order; the tutorial's only where its model is present."""
    from wgpurender.core.scene import load_scene

    out = []
    for name in SCENES:
        path = SCENE_DIR / f"{name}.toml"
        try:
            load_scene(path)
        except UserError:  # the tutorial's model lives outside the repository (../shared/anchors)
            continue
        out.append(path)
    return out


def _live_page(site: Path, step: Step) -> dict[str, str]:
    """The step exported as a live WebGPU page (wgpurender export) under live/KEY/, linked from its section;
    none (with the reason logged on the page) where the browser cannot draw it."""
    from wgpurender.export import export

    size = (step.wgpu.shape[1], step.wgpu.shape[0]) if step.wgpu is not None else STAGE_SIZE
    target = str(SCENE_DIR / f"{step.key}.toml") if (SCENE_DIR / f"{step.key}.toml").is_file() else step.key
    try:
        export(target, site / "live" / step.key, size)
    except UserError as err:
        return {"live_note": str(err)}
    return {"live": f"live/{step.key}/index.html"}


def _write_site(site: Path, steps: list[Step], ctx: GPUContext, seconds: float) -> None:
    images: dict[str, dict[str, str]] = {}
    for step in steps:
        files = images[step.key] = {}
        for kind in ("wgpu", "raw", "heat"):
            pixels = getattr(step, kind)
            if pixels is not None:
                name = f"{step.key}_{kind}.png"
                save_png(site / name, pixels)
                files[kind] = name
        files.update(_live_page(site, step))
    scale, levels = heatmap_scale()
    save_png(site / "heatmap_scale.png", scale)
    pareto = extras.pareto_plot()
    if pareto is not None:
        shutil.copyfile(pareto, site / "accuracy_pareto.png")
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    meta = (f"Built {page.e(stamp)} on {page.e(ctx.describe())} in {seconds:.0f} s with <code>wgpurender report"
            f"</code>. Stages at {STAGE_SIZE[0]}x{STAGE_SIZE[1]}, scenes at {SCENE_SIZE[0]}x{SCENE_SIZE[1]} "
            "(the tutorial's at 320x240); times are "
            "medians of a few frames on this machine (a quick look: <code>wgpurender bench</code> measures). "
            "The heatmap compares the raw-Vulkan image (reference) with the wgpu one.")
    closing = page.closing("accuracy_pareto.png" if pareto else None, extras.hard_cases_table())
    text = page.page("wgpurender: the Vulkan course on wgpu, step by step", meta, steps, images,
                     ("heatmap_scale.png", levels), closing)
    (site / "index.html").write_text(text, encoding="utf-8")
