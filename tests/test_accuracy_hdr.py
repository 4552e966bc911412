"""The HDR target on a bright light (wgpurender/bench/accuracy_hdr.py): an 8-bit scene image clips before the
tone curve, a float one does not.

The truth is checked against the closed form of Reinhard's curve; one small GPU run checks that rgba16float is
far closer to it than rgba8unorm-srgb, whose clipped pixels all come out at the curve's value at 1 (0.5).
"""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.bench import accuracy_hdr as hdr
from wgpurender.bench.accuracy_downsample import linear_from_srgb8


def test_reinhard_is_c_over_one_plus_c():
    assert hdr.reinhard(np.array([0.0, 1.0, 3.0, -2.0])) == pytest.approx([0.0, 0.5, 0.75, 0.0])


def test_the_bright_plane_has_a_hot_spot_above_one():
    size = (48, 36)
    share = hdr.clipped_fraction(size)
    assert 0.2 < share < 0.8  # a hot spot, not the whole plane and not nothing
    truth = hdr.bright_truth(size)
    assert truth.max() > 0.7 and truth.max() < 1.0  # radiance near 3 maps to 0.75: distinguishable


def test_an_8_bit_scene_image_clips_the_hot_spot_and_a_float_one_does_not(ctx, tmp_path):
    """lavapipe 96x72: rgba8unorm-srgb mean linear error 0.05 or more, rgba16float 0.002."""
    from wgpurender.bench.accuracy_analytic import _score, _timed
    from wgpurender.bench.accuracy_fidelity import plane_truth

    size = (48, 36)
    rows = {r.setting: r for r in hdr.run_hdr(ctx, tmp_path, size, 1, 0, _timed, _score)}
    assert rows["rgba16float"].linear_mae < 0.2 * rows["rgba8unorm-srgb"].linear_mae
    assert rows["rgba16float"].linear_mae < 0.01
    hot = (plane_truth(size, hdr.BRIGHT) > 1.05).all(axis=-1)
    clipped = linear_from_srgb8(rows["rgba8unorm-srgb"].m.pixels)[..., :3][hot]
    assert np.abs(clipped - 0.5).max() < 0.01  # min(c, 1) / (1 + min(c, 1)) = 0.5 in every channel
