"""What the window presents, read back from the X server: pixels and size, per present mode and after a resize.

``wgpurender demo`` runs under a private Xvfb; while it is presenting, the test grabs the window's pixels
from the X server (Pillow's XCB screen grab) and compares them with a headless render of the same stage at
the same size (sRGB, within 1/255). So a frame that is rendered but not presented, presented at a stale size,
with the wrong encoding or the wrong present mode's configuration, fails here, not only a non-zero exit code.
The resize is done from outside, as a window manager would (xdotool windowsize). The animation is frozen
(--time 0) so every frame is the same image; the demo is stopped by its PID.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time

import numpy as np
import pytest
from xvfb import private_display

from wgpurender.wgpu_path.render import render_stage

STAGE = "triangle"


@pytest.fixture(scope="module")
def display():
    """A private Xvfb on a display number it picks itself (-displayfd), stopped by PID afterwards."""
    if shutil.which("Xvfb") is None or shutil.which("xdotool") is None:
        pytest.skip("needs Xvfb and xdotool (apt-get install xvfb xdotool)")
    yield from private_display()


def _xdotool(display: str, *args: str) -> str:
    return subprocess.run(["xdotool", *args], env=dict(os.environ, DISPLAY=display), capture_output=True, text=True,
                          timeout=60, check=True).stdout


def _geometry(display: str, window: str) -> tuple[int, int, int, int]:
    """(x, y, width, height) of the window on the screen."""
    values = dict(line.split("=") for line in _xdotool(display, "getwindowgeometry", "--shell", window).split())
    return int(values["X"]), int(values["Y"]), int(values["WIDTH"]), int(values["HEIGHT"])


def _presented(display: str, window: str, size: tuple[int, int], timeout: float = 30.0) -> np.ndarray:
    """The window's pixels on the screen, once the window has the given size and shows a stable frame."""
    from PIL import ImageGrab

    deadline, previous = time.monotonic() + timeout, None
    while time.monotonic() < deadline:
        x, y, w, h = _geometry(display, window)
        if (w, h) == size:
            grab = np.asarray(ImageGrab.grab(bbox=(x, y, x + w, y + h), xdisplay=display).convert("RGB"))
            if previous is not None and np.array_equal(grab, previous) and grab.any():
                return grab.astype(int)
            previous = grab
        time.sleep(0.05)
    pytest.fail(f"the window never showed a stable {size[0]}x{size[1]} frame (last geometry {w}x{h})")


def _expected(ctx, size: tuple[int, int]) -> np.ndarray:
    return render_stage(STAGE, size, "rgba8unorm-srgb", ctx=ctx, frames=1).pixels[..., :3].astype(int)


def _assert_same(got: np.ndarray, want: np.ndarray, what: str) -> None:
    assert got.shape == want.shape, f"{what}: the window shows {got.shape[1]}x{got.shape[0]}, expected " \
                                    f"{want.shape[1]}x{want.shape[0]}"
    off = np.abs(got - want).max(axis=-1)
    assert off.max() <= 1, (f"{what}: {(off > 1).sum()} of {off.size} presented pixels differ from the headless render "
                            f"by more than 1/255 (max {off.max()})")


@pytest.mark.parametrize("mode", ["fifo", "mailbox", "immediate"])
def test_presented_pixels_and_resize(ctx, display, mode):
    """Present a frozen triangle at 160x120, compare the screen with the headless render; resize the window to
    96x72 from outside; the screen must then show the triangle rendered at 96x72."""
    env = dict(os.environ, DISPLAY=display)
    proc = subprocess.Popen([sys.executable, "-m", "wgpurender", "demo", STAGE, "--size", "160x120", "--time", "0",
                             "--present-mode", mode, "--frames", "1000000", "--no-overlay"],  # the scene alone
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if mode == "mailbox":  # wgpu-py 0.32's public API has vsync on/off only: the demo says so at once, exit 2
        stderr = proc.communicate(timeout=120)[1]
        if proc.returncode == 2 and "not offered" in stderr:
            pytest.skip(stderr.strip())
        pytest.fail(f"demo --present-mode mailbox: exit {proc.returncode}: {stderr.strip()}")
    try:
        try:
            window = _xdotool(display, "search", "--sync", "--onlyvisible", "--name", f"wgpurender: {STAGE}").split()[0]
        except subprocess.CalledProcessError:
            proc.kill()
            stderr = proc.communicate(timeout=30)[1]
            if "not offered" in stderr:
                pytest.skip(stderr.strip())
            pytest.fail(f"the demo window never appeared: {stderr.strip()}")
        _assert_same(_presented(display, window, (160, 120)), _expected(ctx, (160, 120)), f"{mode}, 160x120")
        _xdotool(display, "windowsize", window, "96", "72")
        _assert_same(_presented(display, window, (96, 72)), _expected(ctx, (96, 72)), f"{mode}, after resize to 96x72")
        assert proc.poll() is None, f"the demo exited during the test: {proc.communicate()[1]}"
    finally:
        if proc.poll() is None:
            proc.terminate()
            proc.wait(timeout=30)
