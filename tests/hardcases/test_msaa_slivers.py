"""Sub-pixel and sliver triangles under 4x MSAA: resolved coverage against the analytic area (256x256 image).

4096 triangles, each alone in its own 4x4-pixel cell at a uniformly random sub-pixel position (so their coverages
can be read back per cell): "tiny" ones (three vertices within +-0.9 px of a centre, mean area 0.25 px^2) and
"slivers" (1.5..2.6 px long, 0.02..0.3 px wide, random angle). Coverage is read from an rgba16float resolve, exact
in quarters. References, float64: the shoelace area of every triangle, and the sample-point test of the standard 4x
pattern (helpers.STANDARD_4X) / the pixel centre at 1x.

Tolerances (measured on lavapipe, seeds 0..3, in brackets):
- 4x: |sum coverage - sum area| / sum area < 3% [<= 1.6%; the 4-sample estimator's statistical spread is ~1%];
- 4x per-triangle mean |coverage - area| < 0.2 px^2 [0.12..0.14];
- GPU vs sample-point reference: <= 3% of triangles differ (vertices snap to the rasteriser's sub-pixel grid)
  [seed 0: 0.1..0.4% at 1x, 1.0..1.2% at 4x], sums within 1% [<= 0.4%].
- Counter-example, 1x: per-triangle mean error > 0.2 px^2 [0.26..0.30], and over 70% of the triangles vanish
  entirely [75..85%] (4x: under 55%). The 1x *sum* is unbiased too, only noisier [up to 6.8%], so it is not asserted.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import STANDARD_4X
from numerics.coverage import cell_sums, render_coverage, triangle_areas

CELL, GRID = 4, 64
SIZE = (CELL * GRID, CELL * GRID)
N = GRID * GRID


def _cell_origins() -> np.ndarray:
    """Top-left pixel of each cell, row-major (the order cell_sums uses)."""
    return np.stack([np.tile(np.arange(GRID), GRID), np.repeat(np.arange(GRID), GRID)], axis=1) * CELL


def tiny_triangles(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    centres = _cell_origins() + rng.uniform(1.0, 3.0, (N, 2))
    return centres[:, None, :] + rng.uniform(-0.9, 0.9, (N, 3, 2))


def sliver_triangles(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    centres = _cell_origins() + 2.0 + rng.uniform(-0.5, 0.5, (N, 2))
    angle = rng.uniform(0, np.pi, N)
    length, width = rng.uniform(1.5, 2.6, N)[:, None], rng.uniform(0.02, 0.3, N)[:, None]
    along = np.stack([np.cos(angle), np.sin(angle)], axis=1)
    across = np.stack([-along[:, 1], along[:, 0]], axis=1)
    apex = centres + across * width + along * rng.uniform(-0.4, 0.4, (N, 1)) * length
    return np.stack([centres - along * length / 2, centres + along * length / 2, apex], axis=1)


def sample_point_coverage(triangles: np.ndarray, samples: np.ndarray) -> np.ndarray:
    """Per triangle: the fraction of its cell's sample points strictly inside it (float64 edge functions)."""
    offsets = np.stack(np.meshgrid(np.arange(CELL), np.arange(CELL)), axis=-1).reshape(-1, 2)
    points = _cell_origins()[:, None, :] + (offsets[:, None, :] + samples[None]).reshape(-1, 2)[None]
    a, b, c = (triangles[:, i][:, None] for i in range(3))

    def edge(p, q):
        return (q[..., 0] - p[..., 0]) * (points[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (
            points[..., 0] - p[..., 0]
        )

    e = np.stack([edge(a, b), edge(b, c), edge(c, a)])
    inside = (e > 0).all(axis=0) | (e < 0).all(axis=0)
    return inside.sum(axis=1) / len(samples)


SETS = {"tiny": tiny_triangles, "sliver": sliver_triangles}


@pytest.fixture(scope="module", params=list(SETS))
def case(request, ctx):
    triangles = SETS[request.param]()
    assert triangles.min() >= 0 and triangles.max() <= SIZE[0]  # each stays inside its own cell
    areas = triangle_areas(triangles)
    got = {n: cell_sums(render_coverage(ctx, SIZE, triangles, n), CELL) for n in (1, 4)}
    return triangles, areas, got


def test_4x_coverage_sum_matches_area(case):
    _, areas, got = case
    assert abs(got[4].sum() - areas.sum()) / areas.sum() < 0.03
    assert np.abs(got[4] - areas).mean() < 0.2


def test_gpu_matches_sample_point_reference(case):
    triangles, _, got = case
    for n, samples in ((1, np.array([[0.5, 0.5]])), (4, STANDARD_4X)):
        reference = sample_point_coverage(triangles, samples)
        assert (got[n] != reference).mean() <= 0.03
        assert abs(got[n].sum() - reference.sum()) / reference.sum() < 0.01


def test_naive_1x_drops_subpixel_triangles(case):
    """Counter-example: single-sample rendering is all-or-nothing per pixel."""
    _, areas, got = case
    assert np.abs(got[1] - areas).mean() > 0.2
    assert (got[1] == 0).mean() > 0.7
    assert (got[4] == 0).mean() < 0.55
