"""The visual course report: built by the CLI, opened in headless Chromium, and its content checked.

The browser part (tests/browser.py, the DevTools protocol over a pipe) checks what a reader
sees: every image decodes (naturalWidth > 0), nothing is logged as an error (a missing file
is one), and the screenshot is not blank. The content part checks the page against
independent sources: the stage registries' course order, fresh renders of both paths
made in this run, the heatmap against the pixel differences, every file:line pointing
at a def or class, and each scene's plan text.
"""

from __future__ import annotations

import html
import io
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from browser import chromium, open_page
from PIL import Image

from wgpurender.core.imageio import load_png

REPO = Path(__file__).resolve().parent.parent
needs_chromium = pytest.mark.skipif(chromium() is None, reason="chromium is not installed (apt-get install chromium)")
needs_glslc = pytest.mark.skipif(shutil.which("glslc") is None, reason="the raw path needs glslc")


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """`wgpurender report -o DIR`, as a user runs it."""
    if shutil.which("glslc") is None:
        pytest.skip("the raw path needs glslc (apt-get install glslc)")
    out = tmp_path_factory.mktemp("report") / "site"
    result = subprocess.run([sys.executable, "-m", "wgpurender", "report", "-o", str(out)], capture_output=True,
                            text=True, timeout=900)
    assert result.returncode == 0, result.stderr
    return out


def _sections(text: str) -> list[str]:
    return re.findall(r'<section class="step" id="([^"]+)"', text)


def _section(text: str, key: str) -> str:
    start = text.index(f'<section class="step" id="{key}"')
    return text[start:text.index("</section>", start)]


@needs_chromium
def test_the_page_loads_in_a_browser_with_every_image_and_no_errors(site):
    report = open_page(site / "index.html")
    assert report.errors == []
    assert len(report.images) >= 3 * 9  # at least three images for each stage both paths draw
    assert [i["src"] for i in report.images if not (i["complete"] and i["width"] > 0)] == []
    shot = np.asarray(Image.open(io.BytesIO(report.screenshot)).convert("RGB")).astype(int)
    assert shot.shape[:2] == (900, 1200)
    colours = len(np.unique(shot.reshape(-1, 3), axis=0))
    assert shot.std() > 20 and colours > 200, f"screenshot looks blank: std {shot.std():.1f}, {colours} colours"


@needs_chromium
def test_the_browser_check_catches_a_missing_image(site, tmp_path):
    """The check above can fail: delete one image from a copy of the site."""
    copy = tmp_path / "copy"
    shutil.copytree(site, copy)
    (copy / "triangle_raw.png").unlink()
    report = open_page(copy / "index.html")
    assert [i["src"] for i in report.images if i["width"] == 0] == ["triangle_raw.png"]
    assert any("triangle_raw.png" in e for e in report.errors)


def test_one_section_per_course_step_in_course_order(site):
    from wgpurender.core.course.steps import COURSE, stage_steps
    from wgpurender.wgpu_path.stages import all_stages

    text = (site / "index.html").read_text()
    keys = _sections(text)
    stages = [step.stage for step in stage_steps()]  # the course core's table of steps drawn by stage modules
    assert COURSE[-1].scene == "final" and "final" in keys  # step 6, the final model, is the scene section
    assert "course step 6" in _section(text, "final") and "course step 6" not in _section(text, "unlit")
    assert keys[: len(stages)] == stages
    scenes = keys[len(stages):]
    assert scenes[:5] == ["unlit", "retro", "brick", "final_subpass", "final"]
    for key in ("triangle", "3d", "final"):  # the steps' words and the summary are there
        cls = all_stages().get(key)
        if cls is not None:
            assert html.escape(cls.summary) in _section(text, key)


@needs_glslc
def test_the_images_are_both_paths_renders_and_the_heatmap_marks_their_differences(site, ctx):
    from wgpurender.raw_path import render_reference
    from wgpurender.wgpu_path.render import render_stage

    for stage in ("triangle", "3d", "textured"):
        wgpu_img, raw_img = load_png(site / f"{stage}_wgpu.png"), load_png(site / f"{stage}_raw.png")
        assert (wgpu_img == render_stage(stage, (240, 180), ctx=ctx, frames=1).pixels).all()
        assert (raw_img == render_reference(stage, (240, 180))).all()
        heat = load_png(site / f"{stage}_heat.png")
        differs = np.abs(wgpu_img[..., :3].astype(int) - raw_img[..., :3].astype(int)).max(axis=2) > 0
        assert ((heat[..., :3] > 0).any(axis=2) == differs).all()


def test_metrics_and_timings_are_shown_for_both_paths(site):
    from wgpurender.core.compare import compare_images

    text = (site / "index.html").read_text()
    part = _section(text, "3d")
    got = compare_images(load_png(site / "3d_raw.png"), load_png(site / "3d_wgpu.png"))
    psnr = "identical (inf)" if got.psnr == float("inf") else f"{got.psnr:.2f} dB"
    assert psnr in part and f"{got.flip_mean:.5f}" in part
    rows = re.findall(r"<tr><th>(GPU time|frame time) \(median\)</th><td>([^<]+)</td><td>([^<]+)</td>", part)
    assert [r[0] for r in rows] == ["GPU time", "frame time"]
    for _, wgpu_ms, raw_ms in rows:
        for cell in (wgpu_ms, raw_ms):
            assert cell == "n/a" or float(cell.removesuffix(" ms")) > 0


def test_concept_rows_point_at_real_code_on_both_paths(site):
    text = (site / "index.html").read_text()
    part = _section(text, "3d")
    for concept in ("depth/stencil", "push constants", "UBO alignment"):
        assert f"<td>{html.escape(concept)}</td>" in part
    locations = re.findall(r"<small>([\w/.]+\.py):(\d+)</small>", text)
    assert any(p.startswith("wgpurender/raw_path/") for p, _ in locations)
    assert any(p.startswith("wgpurender/wgpu_path/stages/") for p, _ in locations)
    for path, line in set(locations):
        source = (REPO / path).read_text().splitlines()[int(line) - 1].strip()
        assert source.startswith(("def ", "class ", "@", "async def ")), f"{path}:{line} is {source!r}"


def test_scene_sections_show_the_render_plan(site):
    import wgpurender as w

    text = (site / "index.html").read_text()
    # the plan drawn on this adapter, as `render --explain` prints it (the one resolved plan, issue 20)
    plan = w.explain(REPO / "assets" / "scenes" / "final.toml", size=(240, 180)).splitlines()
    assert plan[0].startswith("scene: ") and "scene: assets/scenes/final.toml" in _section(text, "final")
    assert html.escape("\n".join(plan[1:])) in _section(text, "final")  # the plan, all but the file's path
    assert 'src="accuracy_pareto.png"' in text and (site / "accuracy_pareto.png").is_file()
    hard = text[text.index('<section id="hard-cases">'):]
    for case in ("depth precision", "far from origin", "MSAA slivers"):  # rows of docs/numerics.md's table
        assert f"<td>{case}</td>" in hard


def test_report_refuses_a_folder_that_is_not_a_report(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    result = subprocess.run([sys.executable, "-m", "wgpurender", "report", "-o", str(tmp_path)], capture_output=True,
                            text=True, timeout=120, env=dict(os.environ))
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "not empty" in result.stderr
    assert (tmp_path / "notes.txt").read_text() == "mine"
