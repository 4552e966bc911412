"""Browser tests that look at the screen: the page's capture() hook against a DevTools screenshot of the canvas,
and the orbit camera moving the way the window's does (zoom in: the objects grow; a drag to the right: a known
object moves the way core/view/orbit.py's camera projects it), not only "the image changed"."""

from __future__ import annotations

import base64
import io
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from wgpurender.core.scene import load_scene
from wgpurender.core.view.orbit import Orbit, moved_camera
from wgpurender.webpage import export
from wgpurender.webpage.chromium import Chromium, find_chromium

pytestmark = pytest.mark.skipif(find_chromium() is None, reason="chromium is not installed (apt-get install chromium)")
REPO = Path(__file__).resolve().parent.parent
SIZE = (200, 150)
# Two unlit cubes on white, red behind the orbit's centre on the left, blue in front on the right: each one's pixels
# are found by colour alone, and a turn of the orbit moves them apart in opposite directions.
SCENE = """description = "two cubes for the orbit tests"
[camera]
eye = [0.0, 1.0, 6.0]
target = [0.0, 0.0, 0.0]
fov_y = 40.0
[[models]]
path = "{cube}"
material = {{ albedo_color = [1.0, 0.0, 0.0], unlit = true }}
transform = {{ translate = [-1.2, 0.0, -1.5], scale = 0.5 }}
[[models]]
path = "{cube}"
material = {{ albedo_color = [0.0, 0.0, 1.0], unlit = true }}
transform = {{ translate = [1.2, 0.0, 1.5], scale = 0.5 }}
[render]
size = [200, 150]
msaa = 1
hdr = false
clear_color = [1.0, 1.0, 1.0, 1.0]
"""


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    root = tmp_path_factory.mktemp("screen")
    scene = root / "two_cubes.toml"
    scene.write_text(SCENE.format(cube=(REPO / "assets" / "models" / "brick_cube.obj").as_posix()))
    return {"scene": scene, "cubes": export(str(scene), root / "cubes", SIZE).page,
            "triangle": export("triangle", root / "triangle", SIZE).page}


@pytest.fixture(scope="module")
def browser():
    with Chromium(webgpu=True) as session:
        yield session


def _canvas_box(tab) -> list[float]:
    """The canvas's content box in CSS pixels (inside its border)."""
    return tab.evaluate("(() => { const c = document.getElementById('view'), r = c.getBoundingClientRect(); "
                        "return [r.left + c.clientLeft, r.top + c.clientTop, c.clientWidth, c.clientHeight]; })()")


def _screenshot(tab, box) -> np.ndarray:
    x, y, w, h = box
    shot = tab.pipe.send("Page.captureScreenshot", {"format": "png", "clip": {"x": x, "y": y, "width": w,
                         "height": h, "scale": 1}}, session=tab.session)["data"]
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(shot))).convert("RGB"))


def _frames_shown(tab, more: int) -> None:
    tab.evaluate("new Promise((done) => { const start = window.wgpurender.frames; const wait = () => "
                 f"window.wgpurender.frames >= start + {more} ? done(1) : requestAnimationFrame(wait); wait(); }})")


def test_the_screen_shows_what_capture_returns(pages, browser):
    """What a reader sees on the canvas (a DevTools screenshot) is the frame capture() hands the tests."""
    tab = browser.open(pages["triangle"])
    hook = tab.capture()
    _frames_shown(tab, 3)
    seen = _screenshot(tab, _canvas_box(tab))
    assert seen.shape == (SIZE[1], SIZE[0], 3) == hook[..., :3].shape
    assert np.abs(seen.astype(int) - hook[..., :3].astype(int)).max() <= 1
    assert len(np.unique(seen.reshape(-1, 3), axis=0)) > 10  # the triangle, not an empty canvas


def _mask(image: np.ndarray, channel: int) -> np.ndarray:
    """The pixels of the cube whose colour is pure ``channel`` (0 red, 2 blue) on white."""
    rgb = image[..., :3].astype(int)
    others = [c for c in range(3) if c != channel]
    return (rgb[..., channel] > 150) & (rgb[..., others].max(axis=-1) < 100)


def _projected_x(scene, camera, point, width: int, height: int) -> float:
    """Where core's camera puts a world point on screen: pixel column from the left."""
    clip = camera.projection(width / height) @ camera.view() @ np.array([*point, 1.0])
    return (clip[0] / clip[3] + 1) / 2 * width


def _drag(tab, box, dx: float) -> None:
    x, y = box[0] + box[2] / 2, box[1] + box[3] / 2
    tab.mouse("mousePressed", x, y)
    for k in range(1, 9):
        tab.mouse("mouseMoved", x + dx * k / 8, y)
    tab.mouse("mouseReleased", x + dx, y, buttons=0)


def test_zooming_in_makes_the_objects_larger(pages, browser):
    tab = browser.open(pages["cubes"])
    before = tab.capture("{current: true}")
    box = _canvas_box(tab)
    for _ in range(2):  # two wheel steps towards the scene: the distance shrinks to 0.81 of itself
        tab.pipe.send("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": box[0] + 50, "y": box[1] + 50,
                                                   "deltaX": 0, "deltaY": -100}, session=tab.session)
    time.sleep(0.2)
    after = tab.capture("{current: true}")
    for channel in (0, 2):
        grown = _mask(after, channel).sum() / _mask(before, channel).sum()
        assert grown > 1.2, (channel, grown)  # ~1/0.81^2 = 1.52 for a far object; perspective makes it more
    for _ in range(3):  # three steps back: past where it started
        tab.pipe.send("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": box[0] + 50, "y": box[1] + 50,
                                                   "deltaX": 0, "deltaY": 100}, session=tab.session)
    time.sleep(0.2)
    assert _mask(tab.capture("{current: true}"), 0).sum() < _mask(before, 0).sum()  # and out: smaller


def test_a_drag_to_the_right_moves_the_cubes_as_the_window_camera_does(pages, browser):
    """The page and core/view/orbit.py agree: 60 px to the right turns the orbit by 24 degrees; each cube's centre
    moves to where the Python camera projects it, within a few pixels."""
    scene = load_scene(pages["scene"])
    tab = browser.open(pages["cubes"])
    tab.capture()
    before = tab.capture("{current: true}")
    _drag(tab, _canvas_box(tab), 60)
    after = tab.capture("{current: true}")
    orbit = Orbit.from_look_at(scene.camera.eye, scene.camera.target, scene.camera.up)
    orbit.rotate(60, 0)
    turned = moved_camera(scene.camera, orbit)
    for channel, centre in ((0, (-1.2, 0.0, -1.5)), (2, (1.2, 0.0, 1.5))):
        xs_before, xs_after = np.nonzero(_mask(before, channel))[1], np.nonzero(_mask(after, channel))[1]
        start = _projected_x(scene, scene.camera, centre, *SIZE)
        end = _projected_x(scene, turned, centre, *SIZE)
        assert abs(xs_before.mean() - start) < 4, (channel, xs_before.mean(), start)
        assert abs(end - start) > 10  # a move worth measuring
        assert abs(xs_after.mean() - end) < 4, (channel, xs_after.mean(), end)
