"""Depth precision: near 0.01, far 1e5, two camera-facing planes at 1e4 and 1e4 * 1.0005 (64x64 image).

The nearer plane is red, the farther green; a wrong pixel shows green. Both draw orders are rendered: with equal
stored depths the first-drawn plane wins a "less"/"greater" test, so only the far-first order exposes z-fighting.

Analytic reference (float64, transforms.perspective): the stored depths differ by 5.0e-10 with standard Z (both
~0.9999991, where float32 and 24-bit steps are 6e-8) and by 5e-10 absolute / 5.6e-4 relative with reverse-Z (both
~9e-7, where float32's relative step is 6e-8).

Expected (tolerance 0 px, exact counts):
- standard Z, depth24plus: far-first -> every pixel wrong (> 0 required; counter-example);
- reverse-Z, depth24plus: still wrong (fixed-point steps are uniform: reverse-Z needs a float format);
- reverse-Z, depth32float ("greater", clear 0): zero wrong pixels in both orders.
"""

from __future__ import annotations

import pytest
from numerics.depth_planes import DepthScene, render_planes, stored_depth, wrong_pixels

SIZE = (64, 64)
PIXELS = SIZE[0] * SIZE[1]


def test_analytic_depth_gap():
    scene = DepthScene()
    near_z, far_z = -scene.distance, -scene.distance * (1 + scene.gap)
    standard_gap = stored_depth(far_z) - stored_depth(near_z)
    reverse = stored_depth(near_z, reverse_z=True), stored_depth(far_z, reverse_z=True)
    assert 0 < standard_gap < 6e-8 / 10  # far below one float32 / 24-bit step near 1
    assert (reverse[0] - reverse[1]) / reverse[0] > 100 * 2**-23  # over a hundred float32 steps apart


@pytest.mark.parametrize("near_first", [False, True])
def test_reverse_z_float32_has_no_wrong_pixels(ctx, near_first):
    image = render_planes(ctx, SIZE, depth_format="depth32float", reverse_z=True, near_first=near_first)
    assert wrong_pixels(image) == 0
    assert (image[..., 0] > 127).sum() == PIXELS  # the red plane really covers the image


@pytest.mark.parametrize(
    "depth_format, reverse_z",
    [("depth24plus", False), ("depth32float", False), ("depth24plus", True)],
)
def test_naive_depth_setups_z_fight(ctx, depth_format, reverse_z):
    """Counter-examples: the far plane drawn first survives the near one (equal stored depth)."""
    image = render_planes(ctx, SIZE, depth_format=depth_format, reverse_z=reverse_z, near_first=False)
    assert wrong_pixels(image) > 0
