"""compare refuses a threshold that can never fail: a share above 100%, FLIP above 1, max_abs above 255.

README: "a threshold takes a fraction or a percentage (--threshold over_1=0.5%)". A user who writes
``over_1=5`` meaning 5% set 500%, and the check passed whatever the images were (black vs white too): a
silent non-check. The range is known from the metrics' definitions, not from the code: shares of pixels and
FLIP's per-pixel error lie in [0, 1]; a difference of 8-bit values is at most 255.
"""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.cli import main
from wgpurender.core.files.imageio import save_png


def _pair(tmp_path):
    """Black and white 8x8 images: every metric at its worst (over_1 = over_2 = 1, max_abs = 255)."""
    black = np.zeros((8, 8, 4), np.uint8)
    black[..., 3] = 255
    white = np.full((8, 8, 4), 255, np.uint8)
    return str(save_png(tmp_path / "black.png", black)), str(save_png(tmp_path / "white.png", white))


@pytest.mark.parametrize("threshold", ["over_1=5", "over_2=1.5", "over_1=101%", "flip_mean=2", "max_abs=256"])
def test_a_threshold_that_cannot_fail_is_refused(capsys, tmp_path, threshold):
    a, b = _pair(tmp_path)
    try:
        code = main(["compare", a, b, "--threshold", threshold])
    except SystemExit as exit_:  # argparse's refusal
        code = exit_.code
    err = capsys.readouterr().err
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and threshold.split("=")[0] in lines[0] and "Traceback" not in err


@pytest.mark.parametrize("threshold", ["over_1=100%", "over_1=1", "flip_mean=1", "max_abs=255"])
def test_the_limits_themselves_are_accepted(capsys, tmp_path, threshold):
    """At the top of its range a threshold still applies: black vs white has every share at 1 and max_abs 255."""
    a, b = _pair(tmp_path)
    assert main(["compare", a, b, "--threshold", threshold]) == 0


def test_a_share_as_a_fraction_still_fails_when_exceeded(capsys, tmp_path):
    a, b = _pair(tmp_path)
    assert main(["compare", a, b, "--threshold", "over_1=0.99"]) == 1
