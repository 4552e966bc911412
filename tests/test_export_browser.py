"""The exported pages in a real browser (issue 21): every stage and repository scene exported with
``wgpurender export``, opened in one headless Chromium with WebGPU (Dawn on SwiftShader), read back through
``window.wgpurender.capture()`` and compared with wgpu-native's render of the same target and size, within
the calibrated bounds of assets/reference/implementations.toml ([implementations."browser"], with provenance).
The orbit camera, the animation and the page without WebGPU are checked on the same browser's pages.
Skipped only where chromium is not installed.
"""

from __future__ import annotations

import numpy as np
import pytest
from imagecheck import _assert_within

from wgpurender.core.scene import load_scene
from wgpurender.core.verdict.tolerances import Uncalibrated, driver_class, implementation_tolerance, measure
from wgpurender.implementations import all_targets, render_wgpu, target_path
from wgpurender.webpage import NOT_EXPORTABLE, export
from wgpurender.webpage.chromium import Chromium, find_chromium

SIZE = (160, 120)
TARGETS = [n for n in all_targets() if n not in NOT_EXPORTABLE]

pytestmark = pytest.mark.skipif(find_chromium() is None, reason="chromium is not installed (apt-get install chromium)")


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    root = tmp_path_factory.mktemp("pages")
    return {name: export(target_path(name), root / name, SIZE).page for name in TARGETS}


@pytest.fixture(scope="module")
def browser():
    with Chromium(webgpu=True) as session:
        yield session


@pytest.fixture(scope="module")
def captures(pages, browser):
    """Each page's capture() and what the page shows; one browser for all pages."""
    out = {}
    for name, page in pages.items():
        tab = browser.open(page)
        frame = tab.capture()
        shown = tab.evaluate("new Promise((done) => { const poll = () => window.wgpurender.difference ? done({"
                             "adapter: document.getElementById('adapter').textContent, difference: "
                             "window.wgpurender.difference, plan: document.getElementById('plan').textContent, "
                             "error: window.wgpurender.error}) : setTimeout(poll, 50); poll(); })")
        out[name] = (frame, shown, tab.errors())
        tab.close()
    return out


@pytest.mark.parametrize("name", TARGETS)
def test_the_browser_agrees_with_wgpu_native(request, ctx, captures, name):
    image, shown, errors = captures[name]
    assert image.shape == (SIZE[1], SIZE[0], 4)
    assert not errors and shown["error"] is None, (errors, shown["error"])
    assert "swiftshader" in shown["adapter"] or shown["adapter"].strip() not in ("", "none", "(starting)")
    try:
        tol = implementation_tolerance("browser", name, cls=driver_class(ctx.adapter.info["device"]))
    except Uncalibrated as err:
        pytest.skip(str(err))
    wgpu_native = render_wgpu(name, SIZE)
    _assert_within(request, wgpu_native, image, tol)
    assert shown["difference"]["max"] == measure(wgpu_native, image).max_abs  # what the page says about itself
    over_1 = np.mean(np.abs(wgpu_native.astype(int) - image.astype(int)).max(axis=-1) > 1)  # any channel > 1/255
    assert shown["difference"]["over1"] == pytest.approx(over_1, abs=0.5 / image[..., 0].size)


def test_a_scene_page_shows_its_plan_with_the_browser_fallbacks(captures):
    plan = captures["final"][1]["plan"]
    assert "immediates: off" in plan and "lacks 'immediates'" in plan


def test_dragging_the_orbit_camera_changes_the_frame(pages, browser):
    tab = browser.open(pages["final"])
    before = tab.capture("{current: true}")
    box = tab.evaluate("(() => { const r = document.getElementById('view').getBoundingClientRect(); "
                       "return [r.left + r.width / 2, r.top + r.height / 2]; })()")
    tab.mouse("mousePressed", *box)
    for step in range(1, 9):
        tab.mouse("mouseMoved", box[0] + 8 * step, box[1] + 3 * step)
    tab.mouse("mouseReleased", box[0] + 64, box[1] + 24, buttons=0)
    after = tab.capture("{current: true}")
    default = tab.capture()
    assert measure(before, after).changed > 0.05  # 64 px of drag turns the camera by 25.6 degrees
    assert np.array_equal(before, default)  # capture() is still the default camera's frame


def test_the_page_orbit_reproduces_the_scene_camera(pages, browser):
    """The page's look-at (player.js) at the start pose equals the Python camera's view matrix."""
    tab = browser.open(pages["final"])
    tab.evaluate("window.wgpurender.ready")
    js = np.array(tab.evaluate("window.wgpurender.orbitView()"), np.float64).reshape(4, 4).T  # column-major
    python = load_scene(target_path("final")).camera.view()
    np.testing.assert_allclose(js, python, atol=2e-6)


def test_an_animated_stage_shows_different_frames_at_different_times(pages, browser):
    tab = browser.open(pages["3d"])
    first = tab.capture("{time: 0}")
    later = tab.capture("{time: 1.0}")
    assert measure(first, later).changed > 0.01
    seen = tab.evaluate("new Promise((done) => { const start = window.wgpurender.frames; const wait = () => "
                        "window.wgpurender.frames > start + 40 ? done(window.wgpurender.samplesSeen.size) : "
                        "requestAnimationFrame(wait); wait(); })")
    assert seen > 1  # the live loop moved through the recorded frames


def test_without_webgpu_the_page_says_so(pages):
    with Chromium(webgpu=False) as plain:
        tab = plain.open(pages["triangle"])
        shown = tab.evaluate("window.wgpurender.ready.then(() => ({error: window.wgpurender.error, "
                             "message: document.getElementById('message').textContent, "
                             "canvas: getComputedStyle(document.getElementById('view')).display}))")
    assert "WebGPU" in shown["message"] and shown["error"] == shown["message"]
    assert shown["canvas"] == "none"


def test_scrolling_up_on_the_page_moves_the_camera_closer(pages, browser):
    """As the desktop window (core/view/controls.py: "scroll  zoom (closer / farther)"): a wheel turned up
    (deltaY < 0) brings the eye closer to the target, turned down moves it away; the view matrix's translation
    length is the eye's distance."""
    tab = browser.open(pages["final"])
    tab.evaluate("window.wgpurender.ready")
    box = tab.evaluate("(() => { const r = document.getElementById('view').getBoundingClientRect(); "
                       "return [r.left + r.width / 2, r.top + r.height / 2]; })()")

    def distance() -> float:
        view = np.array(tab.evaluate("window.wgpurender.orbitView()"), np.float64).reshape(4, 4).T
        return float(np.linalg.norm(view[:3, 3]))

    def wheel(delta_y: float) -> None:
        tab.pipe.send("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": box[0], "y": box[1], "deltaX": 0,
                                                   "deltaY": delta_y}, session=tab.session)
        tab.evaluate("new Promise((done) => requestAnimationFrame(() => done(true)))")

    start = distance()
    wheel(-100)
    closer = distance()
    wheel(100)
    wheel(100)
    assert closer < start < distance()


def test_the_matrix_renders_into_a_work_folder_it_makes(tmp_path):
    """verify --implementations browser exports into out/work/pages/NAME: the pages folder is made, not refused as a
    missing parent (every browser cell read 'skipped' once export refused missing parents)."""
    from wgpurender.implementations import render_browser

    images, skipped, _ = render_browser(["triangle"], (32, 24), tmp_path / "work" / "pages")
    assert skipped == {} and images["triangle"].shape[:2] == (24, 32)
