"""Course step 2: the first triangle, checked against float64 rasterisation and interpolation."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import barycentric, edge_distance, inside, ndc_to_pixels, pixel_centres, triangle_area

from wgpurender.core.course.triangle import TRIANGLE_COLORS, TRIANGLE_POSITIONS
from wgpurender.wgpu_path.render import render_stage

SIZE = (160, 120)


@pytest.fixture(scope="module")
def image(ctx):
    return render_stage("triangle", SIZE, "rgba8unorm", ctx=ctx, frames=1).pixels


def _tri():
    return ndc_to_pixels(TRIANGLE_POSITIONS, SIZE)


def test_coverage_matches_analytic_triangle(image):
    """Covered pixels are exactly those whose centre is inside the triangle.

    Pixels whose centre lies within 1e-3 px of an edge are excluded: there the
    rasteriser's tie-breaking rule decides, not geometry. The count also matches
    the analytic area within 1% (the pixel-centre sampling error of a 9000 px triangle).
    """
    covered = image[..., :3].astype(int).sum(axis=-1).reshape(-1) > 0
    centres = pixel_centres(SIZE)
    expected = inside(_tri(), centres)
    decided = edge_distance(_tri(), centres) > 1e-3
    assert (covered[decided] == expected[decided]).all()
    area = triangle_area(_tri())
    assert abs(covered.sum() - area) / area < 0.01


def test_colours_interpolate_barycentrically(image):
    """At interior pixel centres the colour is the barycentric mix of the vertex colours (within 1/255 rounding)."""
    tri = _tri()
    points = np.array([[80.5, 60.5], [50.5, 90.5], [100.5, 80.5], [75.5, 30.5], [30.5, 95.5]])
    assert inside(tri, points, eps=0.02).all()
    expected = barycentric(tri, points) @ TRIANGLE_COLORS.astype(np.float64) * 255
    got = image[points[:, 1].astype(int), points[:, 0].astype(int), :3].astype(float)
    assert np.abs(got - expected).max() <= 1.0


@pytest.mark.parametrize("other", ["triangle-buffers", "offscreen"])
def test_variants_give_the_same_image(ctx, image, other):
    """Attribute-less, vertex+index buffers and the offscreen copy are bit-identical."""
    assert np.array_equal(render_stage(other, SIZE, "rgba8unorm", ctx=ctx, frames=1).pixels, image)
