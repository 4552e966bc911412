"""The raw-Vulkan window (wgpurender/raw_path/window.py) under a private Xvfb, on lavapipe, validation on.

Every run here has the validation layer with synchronisation validation on ($WGPURENDER_VALIDATION,
set by conftest.py and passed to the subprocess): any message makes the window raise, so exit code 0
means 0 messages. The screenshot is read back from the presented swapchain image and must equal the
offscreen raw render of the same stage or scene made in this process, bit for bit (threshold 0):
the blit from the stage's rgba8unorm-srgb image to the BGRA sRGB swapchain image (or rgba8unorm to
BGRA UNORM) moves the encoded bytes unchanged on lavapipe (measured: 0 pixels differ).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.imageio import load_png
from wgpurender.raw_path import render_reference

REPO = Path(__file__).resolve().parent.parent
SIZE = (160, 120)


from xvfb import xvfb_display  # noqa: E402,F401 - the shared Xvfb fixture "display" (skips where Xvfb cannot start)


def raw_demo(display, *args, timeout=180):
    env = dict(os.environ, DISPLAY=display, WGPURENDER_VALIDATION="1")
    return subprocess.run([sys.executable, "-m", "wgpurender", "demo", "--raw", *args], env=env,
                          capture_output=True, text=True, timeout=timeout)


@pytest.mark.parametrize("target", ["triangle", "msaa-post", "3d", "assets/scenes/final.toml",
                                    "assets/scenes/retro.toml"])
def test_raw_window_screenshot_equals_offscreen(display, tmp_path, target):
    """3 frames presented through the swapchain, 0 validation messages, screenshot == offscreen raw render."""
    if target.endswith(".toml") and not (REPO / "assets" / "models" / "brick_torus.glb").is_file():
        pytest.skip("scene assets not present")
    shot = tmp_path / "shot.png"
    result = raw_demo(display, str(REPO / target) if target.endswith(".toml") else target, "--frames", "3",
                      "--size", f"{SIZE[0]}x{SIZE[1]}", "--screenshot", str(shot), "--time", "0")
    assert result.returncode == 0, result.stderr
    assert "frames: 3" in result.stdout and "present mode fifo" in result.stdout
    assert "fifo" in result.stdout.split("surface offers:")[1].split("\n")[0]  # FIFO is always offered
    # the demo's default anisotropy rule ("auto"), resolved for the same device by the same function
    want = render_reference(str(REPO / target) if target.endswith(".toml") else target, SIZE, anisotropy="auto")
    got = load_png(shot)
    assert got.shape == want.shape
    assert np.array_equal(got, want), f"{int((got != want).any(-1).sum())} pixels differ"


@pytest.mark.parametrize("mode", ["fifo", "mailbox", "immediate"])
def test_raw_present_modes(display, mode):
    """Each requested present mode is used where offered; otherwise one line naming what is, exit code 2."""
    result = raw_demo(display, "clear-pass", "--frames", "2", "--size", "64x64", "--present-mode", mode)
    if result.returncode == 2 and "not offered" in result.stderr:
        assert "it offers" in result.stderr and "Traceback" not in result.stderr
        pytest.skip(result.stderr.strip())
    assert result.returncode == 0, result.stderr
    assert f"present mode {mode}" in result.stdout


def test_raw_window_resize_and_minimise(display, monkeypatch):
    """In-process: the window is resized to 200x150 after frame 1 and reported minimised for three polls
    after frame 3. The swapchain is re-created, nothing is acquired while minimised, 6 frames are still
    presented, validation stays silent, and the last frame is the 200x150 offscreen render.

    The minimised state is injected (RawWindow.minimised returns True for three polls): Xvfb has no window
    manager, so glfwIconifyWindow has no effect there; the loop's reaction to it is what is tested.
    """
    from wgpurender.raw_path import window as raw_window

    monkeypatch.setenv("DISPLAY", display)
    state = {"calls": 0, "minimised": 0, "acquired_while_minimised": 0}
    real_minimised = raw_window.RawWindow.minimised
    real_frame = raw_window.RawWindow.frame

    def minimised(self):
        if state["minimised"] > 0:
            state["minimised"] -= 1
            return True
        return real_minimised(self)

    def frame(self, *args):
        state["acquired_while_minimised"] += state["minimised"] > 0
        return real_frame(self, *args)

    def on_frame(glfw, window, n):
        state["calls"] += 1
        if n == 1 and "resized" not in state:
            state["resized"] = glfw.set_window_size(window, 200, 150) or True
        if n == 3 and "minimised_once" not in state:
            state["minimised"], state["minimised_once"] = 3, True

    monkeypatch.setattr(raw_window.RawWindow, "minimised", minimised)
    monkeypatch.setattr(raw_window.RawWindow, "frame", frame)
    result = raw_window.run_raw_window("3d", SIZE, frames=6, screenshot=True, fixed_time=0.0, on_frame=on_frame)
    assert result.frames == 6 and state["calls"] >= 6 + 3
    assert result.recreated >= 2  # after the resize, and on restore
    assert "minimised: nothing acquired or drawn" in result.events and state["acquired_while_minimised"] == 0
    assert np.array_equal(result.last_frame, render_reference("3d", (200, 150)))
