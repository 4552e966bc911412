"""FXAA's two draws (mark edges in depth, then FXAA depth-tested on edge pixels; wgpurender/post/fxaa.py)
give exactly the image of the single full-screen draw of the same shader, whose early exit makes the same
decision per pixel. Bit-exact (array_equal): the same arithmetic on the same pixels."""

from __future__ import annotations

import numpy as np
import pytest
from test_post import aliased_edge, hdr_image, run_chain  # noqa: F401  (hdr_image is a fixture)

from wgpurender.post import Fxaa
from wgpurender.post.base import DrawStep


class SingleDrawFxaa(Fxaa):
    """The shader's fs_main alone over every pixel, no depth attachment: FXAA before issue 7."""

    name = "fxaa-single-draw"
    depth_format = None
    steps = (DrawStep("fs_main"),)


@pytest.mark.parametrize("fmt", ["rgba16float", "rgba8unorm-srgb"])
def test_two_draws_equal_one_draw_on_an_aliased_edge(ctx, fmt):
    img = aliased_edge()
    two = run_chain(ctx, [Fxaa()], img, fmt)
    one = run_chain(ctx, [SingleDrawFxaa()], img, fmt)
    np.testing.assert_array_equal(two, one)
    full = 255.0 if fmt.startswith("rgba8") else 1.0
    assert ((two[..., 0] > 0.02 * full) & (two[..., 0] < 0.98 * full)).any(), "FXAA blended some pixels"


def test_two_draws_equal_one_draw_on_noise(ctx, hdr_image):  # noqa: F811
    """Random HDR values: a mix of edge and flat pixels at every threshold, clamped borders included."""
    img = hdr_image.copy()
    img[:, :8] = 0.5  # a flat band, where draw 2 must not write
    two = run_chain(ctx, [Fxaa(edge_threshold=0.3)], img)
    one = run_chain(ctx, [SingleDrawFxaa(edge_threshold=0.3)], img)
    np.testing.assert_array_equal(two, one)
    np.testing.assert_array_equal(two[:, :7], img[:, :7].astype(np.float64))
