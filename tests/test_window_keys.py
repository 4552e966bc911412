"""Windows and notebook under Xvfb: P pauses the animation, F1 hides the overlay (its clicks go to the camera),
the first drag after a click on the overlay is not dropped at a low frame rate, and ``w.show()`` outside Jupyter
opens a window (xdotool finds it and closes it with Esc) or says in one line why it cannot."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from xvfb import xvfb_display  # noqa: F401  (the fixture "display": a private Xvfb)

from wgpurender.core.files.imageio import load_png

REPO = Path(__file__).resolve().parent.parent
SCENE = str(REPO / "assets" / "scenes" / "unlit.toml")


def _demo(display, *args):
    return subprocess.run([sys.executable, "-m", "wgpurender", "demo", *args], capture_output=True, text=True,
                          timeout=240, env=dict(os.environ, DISPLAY=display))


def test_the_clock_stands_still_while_paused_and_resumes_where_it_stopped():
    from wgpurender.core.view.controls import PausableClock

    now = [100.0]
    clock = PausableClock(lambda: now[0])
    now[0] = 103.0
    assert clock.time() == 3.0 and not clock.paused
    clock.toggle()
    now[0] = 110.0
    assert clock.time() == 3.0 and clock.paused  # 7 s paused: the time stood still
    clock.toggle()
    now[0] = 112.0
    assert clock.time() == 5.0  # resumed where it stopped


def test_p_pauses_the_animation_and_says_so(display, tmp_path):
    shots = {}
    for label, keys in (("running", ""), ("paused", "1:key P; ")):
        a, b = tmp_path / f"{label}_a.png", tmp_path / f"{label}_b.png"
        result = _demo(display, "3d", "--frames", "9", "--size", "160x120", "--no-overlay",
                       "--test-input", f"{keys}2:shot {a}; 8:shot {b}")
        assert result.returncode == 0, result.stderr
        shots[label] = (load_png(a), load_png(b), result.stdout)
    running_a, running_b, said = shots["running"]
    assert not np.array_equal(running_a, running_b) and "paused" not in said  # the cubes turn between the shots
    paused_a, paused_b, said = shots["paused"]
    assert np.array_equal(paused_a, paused_b)  # P: the time stands still
    assert "animation paused (P)" in said


@pytest.mark.parametrize("hidden", [False, True])
def test_f1_hides_the_overlay_and_its_clicks_go_to_the_camera(display, tmp_path, hidden):
    """Shown, a click on the MSAA widget turns the knob and a drag on the panel leaves the camera; hidden (F1), the
    same input is the camera's: no knob turns and the drag orbits. Expected images: headless renders."""
    pytest.importorskip("imgui_bundle")
    import wgpurender as w

    after = tmp_path / "after.png"
    f1 = "1:key F1; " if hidden else ""  # after frame 0 drew the panel: the widgets' places are known
    script = f"{f1}2:click msaa=4; 3:move 20 40; 3:press; 4:move 140 60; 4:release; 5:shot {after}"
    result = _demo(display, SCENE, "--frames", "6", "--time", "0", "--size", "320x240", "--test-input", script)
    assert result.returncode == 0, result.stderr
    assert ("overlay hidden (F1)" in result.stdout) == hidden
    assert any(x.startswith("plan:") for x in result.stdout.splitlines()) != hidden, result.stdout
    got = load_png(after)[..., :3].astype(int)
    msaa4 = w.render(SCENE, size=(320, 240), msaa=4).pixels[..., :3].astype(int)
    msaa1 = w.render(SCENE, size=(320, 240), msaa=1).pixels[..., :3].astype(int)
    if hidden:  # the camera turned: far from the start pose at either sample count
        assert min((np.abs(got - m).max(axis=2) > 8).mean() for m in (msaa1, msaa4)) > 0.01
    else:
        assert np.abs(got - msaa4).max() <= 1


def test_the_first_drag_after_a_click_on_the_overlay_is_not_dropped(display, tmp_path):
    """At a low frame rate the panel's release and the press on the scene arrive before the panel is drawn again:
    the drag must turn the camera exactly as the same drag without the panel click before it."""
    pytest.importorskip("imgui_bundle")
    drag = "3:move 560 300; 3:press; 3:move 600 310; 3:move 640 320; 4:release"
    shots = {}
    for label, before in (("after_panel", "2:move 20 20; 2:press; 3:release; "), ("alone", ""), ("none", None)):
        shot = tmp_path / f"{label}.png"
        script = f"{before}{drag}; 5:shot {shot}" if before is not None else f"5:shot {shot}"
        result = _demo(display, SCENE, "--frames", "6", "--time", "0", "--size", "640x480", "--test-input", script)
        assert result.returncode == 0, result.stderr
        shots[label] = load_png(shot)
    assert not np.array_equal(shots["alone"], shots["none"])  # the drag turns the camera
    assert np.array_equal(shots["after_panel"], shots["alone"])  # and is not lost after a click on the panel


def _show(display, code: str, **env) -> subprocess.Popen:
    environ = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    if display:
        environ["DISPLAY"] = display
    return subprocess.Popen([sys.executable, "-c", code], env={**environ, **env}, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


@pytest.mark.skipif(shutil.which("xdotool") is None, reason="xdotool is not installed (apt-get install xdotool)")
def test_show_outside_jupyter_opens_a_window_that_esc_closes(display):
    proc = _show(display, "import wgpurender as w; print('returned', w.show('triangle', size=(160, 120)))")
    try:
        found = subprocess.run(["xdotool", "search", "--sync", "--name", "wgpurender: triangle"], capture_output=True,
                               text=True, timeout=120, env=dict(os.environ, DISPLAY=display))
        window = found.stdout.split()[0]
        time.sleep(0.5)
        subprocess.run(["xdotool", "windowfocus", "--sync", window, "key", "Escape"], check=True, timeout=30,
                       env=dict(os.environ, DISPLAY=display))
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
    assert out.strip() == "returned None"  # the window closed, nothing else to hand back


def test_show_without_a_display_says_why_in_one_line():
    proc = _show(None, "import wgpurender as w; img = w.show('triangle', size=(64, 48)); print(img.pixels.shape)")
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err
    lines = [x for x in err.splitlines() if x.startswith("w.show:")]
    assert len(lines) == 1 and "no display" in lines[0], err
    assert out.strip() == "(48, 64, 4)"  # the still frame instead
