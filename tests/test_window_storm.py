"""The window storm: the final scene in a GLFW window under Xvfb while the window is resized from 1x1 to 3000x40,
minimised, restored, unmapped and mapped again, frame after frame. It must keep presenting (no hang, bounded by
the subprocess timeout), end cleanly, print nothing on stderr, and have drawn at the extreme sizes."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from test_window import display  # noqa: F401 - the Xvfb fixture

HERE = Path(__file__).resolve().parent
FINAL = HERE.parent / "assets" / "scenes" / "final.toml"
FRAMES = 36  # two rounds of the driver's 18 steps


def test_window_storm_keeps_presenting(display):  # noqa: F811
    env = dict(os.environ, DISPLAY=display, PYTHONPATH=str(HERE.parent))
    result = subprocess.run([sys.executable, str(HERE / "window_storm_driver.py"), str(FINAL), str(FRAMES)],
                            env=env, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr[-3000:]
    assert result.stderr == ""
    report = json.loads(result.stdout.strip().splitlines()[-1])
    assert report["frames"] == FRAMES
    sizes = {tuple(s) for s in report["sizes"]}
    assert (1, 1) in sizes and (3000, 40) in sizes, sizes  # drawn at both extremes
