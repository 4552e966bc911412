"""Course step 3b: 4x MSAA against the analytic coverage of the standard sample positions.

The triangle's vertex colours are red, green and blue, so at every interior point
R + G + B = 1: the channel sum of a pixel measures its coverage independent of
where in the triangle it lies.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import STANDARD_4X, edge_distance, inside, ndc_to_pixels, pixel_centres

from wgpurender.core.course.triangle import TRIANGLE_POSITIONS
from wgpurender.wgpu_path.render import render_stage

SIZE = (96, 72)


@pytest.fixture(scope="module")
def images(ctx):
    return {n: render_stage("msaa", SIZE, "rgba8unorm", msaa=n, ctx=ctx, frames=1).pixels for n in (1, 4)}


def _coverage(img):
    return img[..., :3].astype(float).sum(axis=-1).reshape(-1) / 255.0


def _sample_coverage():
    """Fraction of the 4 standard sample positions inside the triangle, per pixel."""
    tri = ndc_to_pixels(TRIANGLE_POSITIONS, SIZE)
    corners = pixel_centres(SIZE) - 0.5
    hits = np.zeros(len(corners))
    near_tie = np.zeros(len(corners), dtype=bool)
    for offset in STANDARD_4X:
        pts = corners + offset
        hits += inside(tri, pts)
        near_tie |= edge_distance(tri, pts) < 1e-3
    return hits / 4, near_tie


def test_1x_has_only_two_flat_values(images):
    """Without MSAA every pixel is either background (sum 0) or fully covered (sum 1, within 2/255 rounding)."""
    cov = _coverage(images[1])
    assert ((cov == 0) | (np.abs(cov - 1) <= 2 / 255)).all()


def test_4x_edges_take_intermediate_values(images):
    cov = _coverage(images[4])
    partial = (cov > 0.1) & (cov < 0.9)
    assert partial.sum() > 100  # the three edges, ~250 px long in all


def test_4x_resolve_matches_analytic_sample_coverage(images):
    """Each resolved pixel's coverage equals k/4, k = samples inside, within 2/255 (unorm rounding of 3 channels)."""
    expected, near_tie = _sample_coverage()
    cov = _coverage(images[4])
    assert np.abs(cov - expected)[~near_tie].max() <= 2.5 / 255


def test_interiors_identical(images):
    """Away from edges, MSAA changes nothing: the shader runs once per pixel at its centre either way."""
    tri = ndc_to_pixels(TRIANGLE_POSITIONS, SIZE)
    interior = inside(tri, pixel_centres(SIZE)) & (edge_distance(tri, pixel_centres(SIZE)) > 1.0)
    a, b = images[1].reshape(-1, 4), images[4].reshape(-1, 4)
    assert interior.sum() > 1000
    assert np.array_equal(a[interior], b[interior])
