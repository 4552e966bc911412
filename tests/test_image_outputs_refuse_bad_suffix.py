"""Every image a command writes follows the suffix rule that render and reference follow (README, "Output files"):
the suffix picks the format, and an unknown suffix is refused before anything runs (exit 2), never written as a
PNG under a misleading name. ``compare --heatmap h.txt`` and ``demo --screenshot s.txt`` wrote PNG bytes into
a .txt file (and exited 0).
"""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from wgpurender.cli import main
from wgpurender.core.files.imageio import save_png


def _code(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as exit_:  # argparse's refusal
        return exit_.code


def _pair(tmp_path):
    a = np.full((6, 5, 4), 200, np.uint8)
    b = a.copy()
    b[0, 0, :3] = 0
    return str(save_png(tmp_path / "a.png", a)), str(save_png(tmp_path / "b.png", b))


def test_compare_heatmap_refuses_an_unknown_suffix(capsys, tmp_path):
    a, b = _pair(tmp_path)
    heat = tmp_path / "h.txt"
    assert _code(["compare", a, b, "--heatmap", str(heat)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'.txt'" in err[0] and ".png" in err[0]
    assert not heat.exists()


def test_compare_heatmap_format_follows_the_suffix(capsys, tmp_path):
    a, b = _pair(tmp_path)
    heat = tmp_path / "h.jpg"
    assert _code(["compare", a, b, "--heatmap", str(heat), "--threshold", "max_abs=255"]) == 0
    with Image.open(heat) as im:
        assert im.format == "JPEG" and im.mode == "RGB"  # JPEG bytes, not PNG ones under a .jpg name


@pytest.mark.parametrize("raw", [False, True])
def test_demo_screenshot_refuses_an_unknown_suffix_before_a_window(capsys, tmp_path, monkeypatch, raw):
    monkeypatch.delenv("DISPLAY", raising=False)  # no window could open: the refusal must come first
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    shot = tmp_path / "s.txt"
    argv = ["demo", *(["--raw"] if raw else []), "triangle", "--frames", "1", "--screenshot", str(shot)]
    assert _code(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'.txt'" in err[0]
    assert not shot.exists()
