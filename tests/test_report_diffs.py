"""The report's page parts without building a report: step-to-step diffs (report/diffs.py) against the sources
they come from, excerpt lines each numbered in its own element (so they can wrap), and an image's click target."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from wgpurender.report import code, page
from wgpurender.report.diffs import step_diffs


def _step(key: str) -> SimpleNamespace:
    from wgpurender.raw_path.stages import all_ref_stages
    from wgpurender.wgpu_path.stages import all_stages

    locations = code.stage_locations(all_stages().get(key), all_ref_stages().get(key))
    return SimpleNamespace(key=key, code=code.excerpts(locations), diffs={})


def _lines(step, side) -> set[str]:
    return {line.strip() for x in step.code[side] for line in x.source.splitlines()}


def test_a_diff_adds_this_steps_lines_and_removes_the_previous_ones():
    steps = [_step("triangle"), _step("triangle-buffers")]
    step_diffs(steps)
    first, second = steps
    assert first.diffs == {}  # nothing before the first step
    for side in ("wgpu", "raw"):
        d = second.diffs[side]
        assert d.previous == "triangle"
        added = [x[1:].strip() for x in d.lines if x.startswith("+") and not x.startswith("+++")]
        removed = [x[1:].strip() for x in d.lines if x.startswith("-") and not x.startswith("---")]
        assert d.added == len(added) > 0 and d.removed == len(removed) > 0
        code_added = [x for x in added if x and not x.startswith("# ")]
        code_removed = [x for x in removed if x and not x.startswith("# ")]
        assert all(x in _lines(second, side) for x in code_added)
        assert any(x not in _lines(first, side) for x in code_added)
        assert all(x in _lines(first, side) for x in code_removed)
        assert any(x not in _lines(second, side) for x in code_removed)


def test_the_same_code_twice_is_an_empty_diff_from_the_step_just_before():
    steps = [_step("triangle"), _step("msaa"), _step("msaa")]
    step_diffs(steps)
    assert steps[2].diffs["wgpu"].previous == "msaa" and steps[2].diffs["wgpu"].lines == []
    assert "the same code as msaa" in page._diffs(steps[2])


def test_each_excerpt_line_is_its_own_numbered_element():
    x = code.excerpt("wgpu", "scene.frame:SceneRenderer.record")
    numbers = [int(n) for n in __import__("re").findall(r'<span class="line" data-line="(\d+)">', x.html)]
    assert numbers == list(range(x.first, x.last + 1))
    assert 'id="' not in x.html  # one page shows an excerpt in several steps: no duplicate ids


def test_a_click_on_an_image_opens_its_larger_render():
    step = SimpleNamespace(key="s", large={"wgpu": np.zeros((960, 1280, 4), np.uint8)}, lanes=[],
                           wgpu=np.zeros((480, 640, 4), np.uint8), raw=None)
    html = page._figure({"wgpu": "s_wgpu.png", "wgpu_large": "s_wgpu_large.png"}, "wgpu", "", step, "wgpu")
    assert 'href="s_wgpu_large.png"' in html and 'src="s_wgpu.png"' in html and "click: 1280x960" in html


def test_the_click_target_is_twice_the_page_image_on_both_sides():
    from wgpurender.report.steps import larger

    assert larger((640, 480)) == (1280, 960) and larger((320, 200)) == (640, 400)
