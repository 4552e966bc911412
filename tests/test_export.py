"""wgpurender export without a browser: what the page is made of (the browser itself: test_export_browser.py)."""

from __future__ import annotations

import json

import pytest

from wgpurender.core.errors import UserError
from wgpurender.implementations import render_wgpu, target_path
from wgpurender.webpage import NOT_EXPORTABLE, export


def _data(page) -> dict:
    text = (page.parent / "data.js").read_text()
    return json.loads(text[text.index("=") + 1:].rstrip().rstrip(";"))


def test_a_render_in_the_same_process_does_not_leak_into_the_recording(ctx, tmp_path):
    """The path caches objects on the device; a recording must make its own, or the page could not name them."""
    render_wgpu("final", (64, 48))
    done = export(target_path("final"), tmp_path / "final", (64, 48))
    data = _data(done.page)
    made = {c["r"] for c in data["setup"] if "r" in c} | {data["meta"]["device"]}
    used = {v["$"] for c in data["setup"] + data["frame"] for v in _refs(c)}
    assert used <= made | {c["r"] for c in data["frame"] if "r" in c}


def _refs(value):
    if isinstance(value, dict):
        if "$" in value:
            yield value
        for k, v in value.items():
            if k not in ("o", "r"):
                yield from _refs(v)
    elif isinstance(value, list):
        for v in value:
            yield from _refs(v)


def test_the_page_replays_the_browser_plan_without_immediates(ctx, tmp_path):
    data = _data(export(target_path("unlit"), tmp_path / "unlit", (64, 48)).page)
    assert "immediates: off" in data["meta"]["plan"]
    assert not any(c.get("m") == "setImmediates" for c in data["setup"] + data["frame"])
    shader = next(c["d"]["code"] for c in data["setup"] if c.get("m") == "createShaderModule")
    assert "var<immediate>" not in shader and "var<uniform> material" in shader


@pytest.mark.parametrize("name", sorted(NOT_EXPORTABLE))
def test_a_stage_the_browser_cannot_draw_is_refused(name, tmp_path):
    with pytest.raises(UserError, match="clearTexture"):
        export(name, tmp_path / name, (64, 48))


def test_a_file_as_the_output_folder_is_refused(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(UserError, match="not a folder"):
        export("triangle", tmp_path / "f", (64, 48))


def test_each_report_step_links_its_live_page_or_says_why_not(tmp_path):
    """The report (wgpurender/report) exports every step next to the site and links it from the section."""
    import numpy as np

    from wgpurender.report import page
    from wgpurender.report.build import _live_page
    from wgpurender.report.steps import Step

    step = Step("triangle", "triangle", "2a", "", [], wgpu=np.zeros((48, 64, 4), np.uint8))
    files = _live_page(tmp_path, step)
    assert (tmp_path / files["live"]).is_file() and (tmp_path / "live" / "triangle" / "data.js").is_file()
    assert f'href="{files["live"]}"' in page._live(files)
    refused = _live_page(tmp_path, Step("clear", "clear", "1a", "", []))
    assert "clearTexture" in page._live(refused)
