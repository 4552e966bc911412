"""The demo's settings overlay (wgpu_path/window/overlay.py, imgui-bundle through wgpu-py's backend) under Xvfb.

A knob is clicked where a user clicks it (``--test-input click NAME`` moves the pointer to the widget's centre
as ImGui laid it out, presses, and releases on the next frame). Expected images are headless renders made here
with the knob's value; the plan's change is the line the window prints.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from xvfb import xvfb_display  # noqa: F401  (the fixture "display": a private Xvfb)

from wgpurender.core.files.imageio import load_png

pytest.importorskip("imgui_bundle")
REPO = Path(__file__).resolve().parent.parent
SCENE = str(REPO / "assets" / "scenes" / "unlit.toml")
SIZE = (160, 120)


def _demo(display, *args):
    return subprocess.run([sys.executable, "-m", "wgpurender", "demo", *args], capture_output=True, text=True,
                          timeout=240, env=dict(os.environ, DISPLAY=display))


def test_the_msaa_toggle_changes_the_image_and_the_plan(display, tmp_path):
    import wgpurender as w

    before, after = tmp_path / "before.png", tmp_path / "after.png"
    script = f"0:shot {before}; 2:click msaa=4; 5:shot {after}"
    result = _demo(display, SCENE, "--frames", "6", "--time", "0", "--size", f"{SIZE[0]}x{SIZE[1]}",
                   "--test-input", script)
    assert result.returncode == 0, result.stderr
    lines = [x for x in result.stdout.splitlines() if x.startswith("plan:")]
    assert len(lines) == 1 and "msaa 1 -> 4" in lines[0] and "attachments (2 -> 3)" in lines[0], result.stdout
    a, b = load_png(before).astype(int), load_png(after).astype(int)
    for got, msaa in ((a, 1), (b, 4)):  # each is the headless render with that sample count
        want = w.render(SCENE, size=SIZE, msaa=msaa).pixels.astype(int)
        assert np.abs(got[..., :3] - want[..., :3]).max() <= 1, f"msaa {msaa}"
    edges = (np.abs(b - a)[..., :3].max(axis=2) > 8).sum()
    assert edges > 20, f"MSAA changed only {edges} pixels"


def test_a_click_on_the_panel_does_not_turn_the_camera(display, tmp_path):
    """A drag that starts on the panel belongs to the panel: the scene stays where it was."""
    still, dragged = tmp_path / "still.png", tmp_path / "dragged.png"
    script = f"0:shot {still}; 2:move 20 40; 2:press; 3:move 140 60; 3:release; 4:shot {dragged}"
    result = _demo(display, SCENE, "--frames", "5", "--time", "0", "--size", "320x240", "--test-input", script)
    assert result.returncode == 0, result.stderr
    assert np.array_equal(load_png(still), load_png(dragged))


def test_no_overlay_has_no_widgets_to_click(display):
    result = _demo(display, SCENE, "--frames", "3", "--no-overlay", "--test-input", "1:click msaa=4")
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and "no overlay" in result.stderr
    raw = _demo(display, "--raw", "triangle", "--frames", "1", "--no-overlay")
    assert raw.returncode == 2 and "raw window has none" in raw.stderr
