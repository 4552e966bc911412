"""The window path under a private Xvfb: the demo presents frames and its screenshot is the rendered image."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
from xvfb import private_display

from wgpurender.core.files.imageio import load_png
from wgpurender.wgpu_path.render import render_stage


@pytest.fixture(scope="module")
def display():
    """Start Xvfb on a display number it picks itself (-displayfd), stop it by PID afterwards."""
    if shutil.which("Xvfb") is None:
        pytest.skip("Xvfb is not installed (apt-get install xvfb)")
    yield from private_display()


def _demo(display, *args, timeout=120):
    env = dict(os.environ, DISPLAY=display)
    return subprocess.run(
        [sys.executable, "-m", "wgpurender", "demo", *args], env=env, capture_output=True, text=True, timeout=timeout
    )


@pytest.mark.parametrize("stage", ["triangle", "msaa"])
def test_demo_screenshot_matches_headless(ctx, display, tmp_path, stage):
    """The last presented frame equals the headless render of the same stage (sRGB, within 1/255)."""
    shot = tmp_path / "shot.png"
    result = _demo(display, stage, "--frames", "3", "--size", "160x120", "--screenshot", str(shot))
    assert result.returncode == 0, result.stderr
    assert "frames: 3" in result.stdout
    got = load_png(shot).astype(int)
    want = render_stage(stage, (160, 120), "rgba8unorm-srgb", ctx=ctx, frames=1).pixels.astype(int)
    assert got.shape == want.shape
    assert np.abs(got[..., :3] - want[..., :3]).max() <= 1


@pytest.mark.parametrize("mode", ["fifo", "immediate"])
def test_present_modes(display, mode):
    result = _demo(display, "clear-pass", "--frames", "2", "--size", "64x64", "--present-mode", mode)
    if result.returncode == 2 and "not offered" in result.stderr:
        pytest.skip(result.stderr.strip())
    assert result.returncode == 0, result.stderr
