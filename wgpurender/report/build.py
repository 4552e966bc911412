"""Build the report site: every step rendered, compared and timed, then the page and its PNGs written at once.

The site is built in a staging folder beside ``out_dir`` and copied into place (file by file, atomically) when
it is complete, so a failed build leaves the previous report. ``out_dir`` is shared with the user: only the
files a report wrote there (its manifest, core/files/owned_files.py) are replaced or removed.
"""

from __future__ import annotations

import datetime
import time
from collections.abc import Callable
from pathlib import Path

from wgpurender.core.errors import UserError
from wgpurender.core.files.assets import scene_dir
from wgpurender.core.files.imageio import save_png
from wgpurender.core.files.owned_files import OwnedFolder, install, staging, sweep_stale_builds
from wgpurender.core.files.safe_write import cleanup_on_signal
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.report import code, extras, page
from wgpurender.report.diffs import step_diffs
from wgpurender.report.steps import Step, heatmap_scale, missing_scene_step, scene_step, stage_step
from wgpurender.wgpu_path.device.context import GPUContext, get_context

REPO_ROOT = Path(__file__).resolve().parents[2]
SCENE_DIR = scene_dir()  # the checkout's assets/scenes, or the wheel's copy
# Scene files in course order: the minimal plan first, the complete scene, then the C++ tutorial's chapters
# (those read the tutorial's model from ../shared/anchors and are left out where it is missing).
SCENES = ("unlit", "retro", "brick", "final_subpass", "final", "vulkan_tutorial_28", "vulkan_tutorial_30")
# A projector's page (1280 px wide): every image at least 640 px wide; a click opens the wgpu image at twice that
# size (steps.larger). lavapipe's anisotropic filtering is pathological at some sizes (notes/facts.md): brick.toml
# took 11 s a frame at 320x240 but 0.2 s at 240x180; vulkan_tutorial_28.toml 17 s a frame at 240x180 but 0.5 s at
# 320x240, 0.08 s at 800x600.
STAGE_SIZE = (640, 480)
SCENE_SIZE = (640, 480)
SCENE_SIZES: dict[str, tuple[int, int]] = {}
MAX_SHOT_WIDTH = 640  # images wider than this are shown at this width; a click opens the larger render


def course_stages() -> list[str]:
    """Stage names of both paths in course order (course/steps.py); a stage only one path has is a step too."""
    from wgpurender.core.course.steps import course_position
    from wgpurender.raw_path.stages import all_ref_stages
    from wgpurender.wgpu_path.stages import all_stages

    return sorted(set(all_stages()) | set(all_ref_stages()), key=course_position)


def check_out_dir(out_dir: Path, force: bool = False) -> OwnedFolder:
    """The site's folder, checked before any step is rendered: new, empty, or an earlier output (its manifest);
    ``force`` writes beside other files. A build killed earlier left its staging folder: swept here."""
    folder = OwnedFolder(out_dir, "report", force or _legacy_report(out_dir), "cannot write the report to")
    sweep_stale_builds(folder.folder.parent)
    return folder


def _legacy_report(out_dir: Path) -> bool:
    """A report built before manifests existed (its index.html carries the generator mark, no manifest): written
    as with --force, beside its files (none of which is deleted: which ones it wrote is not known)."""
    from wgpurender.core.files.owned_files import read_manifest

    index = out_dir / "index.html"
    if not out_dir.is_dir() or out_dir.is_symlink() or index.is_symlink() or not index.is_file():
        return False
    head = index.open("rb").read(4096).decode("utf-8", "replace")
    return read_manifest(out_dir) is None and page.GENERATOR_MARK in head


def build_report(out_dir: str | Path, *, size: tuple[int, int] | None = None, stages: list[str] | None = None,
                 scenes: list[Path] | None = None, ctx: GPUContext | None = None,
                 log: Callable[[str], None] = print, accuracy: bool = True,
                 anisotropy: str = DEFAULT_ANISOTROPY, force: bool = False) -> Path:
    """Render every step on both paths, measure accuracy, and write the site; returns the path of index.html.

    ``size``: every step's image size (default 640x480; a click opens each path's render at twice it).
    ``accuracy=False`` leaves out the accuracy and hard-case measurements (about half a minute on lavapipe; the
    page says so). ``anisotropy``: the scenes' rule (core/plan/anisotropy.py), as ``render --anisotropy``.
    ``force``: write into a non-empty folder without an earlier output, beside its files
    (core/files/owned_files.py).
    """
    folder = check_out_dir(Path(out_dir), force)
    ctx = ctx or get_context()
    start = time.perf_counter()
    steps: list[Step] = []
    for name in course_stages() if stages is None else stages:
        log(f"stage {name}")
        steps.append(stage_step(ctx, name, size or STAGE_SIZE, log))
    for path, missing in _scene_files() if scenes is None else [(Path(p), "") for p in scenes]:
        log(f"scene {path.name}" + (f": {missing}" if missing else ""))
        if missing:
            steps.append(missing_scene_step(path, missing))
        else:
            steps.append(scene_step(ctx, path, size or SCENE_SIZES.get(path.stem, SCENE_SIZE), log, anisotropy))
    step_diffs(steps)
    with cleanup_on_signal(), staging(folder) as tmp:  # SIGTERM while the staging folder exists ends via finally
        measured = extras.measure(ctx, tmp, log) if accuracy else None
        _write_site(tmp, steps, ctx, start, measured, size)
        install(folder, tmp)
    out_dir = folder.folder
    log(f"report: {len(steps)} steps in {time.perf_counter() - start:.1f} s")
    return out_dir / "index.html"


def _scene_files() -> list[tuple[Path, str]]:
    """The repository's scenes in course order, each with "" or the one line saying why it cannot be rendered
    here (the tutorial's model and texture live outside the repository, in ../shared/anchors)."""
    from wgpurender.core.scene import load_scene

    out = []
    for name in SCENES:
        path = SCENE_DIR / f"{name}.toml"
        try:
            load_scene(path)
        except UserError as err:
            out.append((path, missing_line(path, str(err).splitlines()[0])))
            continue
        out.append((path, ""))
    return out


def missing_line(path: Path, error: str) -> str:
    """One line for a scene that cannot load: what is missing, and where to get it."""
    text = path.read_text(encoding="utf-8")
    if "anchors" in text:
        import tomllib

        # where the scene itself looks (its model's path, relative to it): beside a wheel's site-packages too
        where = (path.parent / tomllib.loads(text)["models"][0]["path"]).resolve().parent
        return (f"Not rendered: {path.name} draws the Vulkan tutorial's viking room, whose model and texture "
                f"are not in the repository and are absent here (looked for in {where}); docs/guide.md, \"Where the "
                f"tutorial's files come from\", says how to fetch them.")
    return f"Not rendered: {error}"


def _live_page(site: Path, step: Step) -> dict[str, str]:
    """The step exported as a live WebGPU page (wgpurender export) under live/KEY/, linked from its section;
    none (with the reason logged on the page) where the browser cannot draw it."""
    from wgpurender.webpage import export

    if step.missing:
        return {}

    size = (step.wgpu.shape[1], step.wgpu.shape[0]) if step.wgpu is not None else STAGE_SIZE
    target = str(SCENE_DIR / f"{step.key}.toml") if (SCENE_DIR / f"{step.key}.toml").is_file() else step.key
    (site / "live").mkdir(exist_ok=True)
    try:
        export(target, site / "live" / step.key, size)
    except UserError as err:
        return {"live_note": str(err)}
    return {"live": f"live/{step.key}/index.html"}


def _write_site(site: Path, steps: list[Step], ctx: GPUContext, start: float, measured: extras.Measured | None,
                size: tuple[int, int] | None) -> None:
    """``start``: the build's perf_counter at its start; the page states the time from there to its writing, once
    (the accuracy measurement is inside it: it was added a second time)."""
    images: dict[str, dict[str, str]] = {}
    for step in steps:
        files = images[step.key] = {}
        for kind in ("wgpu", "raw", "heat"):
            pixels = getattr(step, kind)
            if pixels is not None:
                name = f"{step.key}_{kind}.png"
                save_png(site / name, pixels)
                files[kind] = name
        for kind, pixels in step.large.items():
            name = f"{step.key}_{kind}_large.png"
            save_png(site / name, pixels)
            files[f"{kind}_large"] = name
        files.update(_live_page(site, step))
    scale, levels = heatmap_scale()
    save_png(site / "heatmap_scale.png", scale)
    _write_listings(site, steps)
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    sizes = (f"every step at {size[0]}x{size[1]}" if size else f"stages at {STAGE_SIZE[0]}x{STAGE_SIZE[1]}, "
             f"scenes at {SCENE_SIZE[0]}x{SCENE_SIZE[1]}")
    meta = (f"Built {page.e(stamp)} on {page.e(ctx.describe())} in {time.perf_counter() - start:.0f} s with "
            f"<code>wgpurender report</code>: {sizes}. Times are medians of a few frames on this machine (a quick "
            "look: <code>wgpurender bench</code> measures). The heatmap compares the raw-Vulkan image (reference) "
            "with the wgpu one. Click an image to open it rendered at twice the size, a file name to read the whole "
            "file.")
    width = min((size or STAGE_SIZE)[0], MAX_SHOT_WIDTH)
    text = page.page("wgpurender: the Vulkan course on wgpu, step by step", meta, steps, images,
                     ("heatmap_scale.png", levels), page.closing(measured), shot_width=width)
    (site / "index.html").write_text(text, encoding="utf-8")


def _write_listings(site: Path, steps: list[Step]) -> None:
    """Every source file an excerpt comes from, highlighted whole, beside the page (code/<path>.html)."""
    for path in sorted({x.path for step in steps for side in step.code.values() for x in side}):
        target = site / code.listing_name(path)
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(code.listing(path), encoding="utf-8")
