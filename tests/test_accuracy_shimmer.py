"""Shimmer under slow motion (wgpurender/bench/accuracy_shimmer.py): what mip-maps and MSAA are for.

The measure is checked on arrays whose answer is written here; the moving truths against closed forms (a
translated image keeps its coverage and moves its centroid by the step; a forward-moving eye changes the
footprint integral, not its mean colour on a constant texture); and one small GPU run checks the orderings the
course teaches: trilinear beats nearest and bilinear on the minified plane, MSAA 4x beats none on edge crawl.
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

from wgpurender.bench import accuracy_shimmer as sh
from wgpurender.bench import accuracy_truth as truth
from wgpurender.bench.accuracy_analytic import triangle_shapes


def test_shimmer_is_the_error_of_the_frame_to_frame_change():
    rng = np.random.default_rng(3)
    truths = rng.uniform(size=(4, 5, 6, 3))
    assert sh.shimmer(truths + 0.25, truths) == pytest.approx(0.0, abs=1e-12)  # a constant error does not shimmer
    frozen = np.repeat(truths[:1], 4, axis=0)  # a renderer that does not move: misses all of the truth's change
    assert sh.shimmer(frozen, truths) == pytest.approx(np.abs(np.diff(truths, axis=0)).mean())
    flicker = truths.copy()
    flicker[1::2] += 0.1  # every other frame 0.1 too bright: each change off by 0.1
    assert sh.shimmer(flicker, truths) == pytest.approx(0.1)


def test_shimmer_refuses_a_single_frame_or_mismatched_shapes():
    with pytest.raises(ValueError, match="two or more frames"):
        sh.shimmer(np.zeros((1, 2, 2, 3)), np.zeros((1, 2, 2, 3)))
    with pytest.raises(ValueError, match="two or more frames"):
        sh.shimmer(np.zeros((3, 2, 2, 3)), np.zeros((3, 2, 3, 3)))


def test_row_reports_still_error_and_the_truths_own_change():
    truths = np.zeros((3, 2, 2, 3))
    truths[1] = 0.5
    r = sh.row("edges", "x", truths + 0.1, truths)
    assert (r.shimmer, r.still_error, r.truth_change) == pytest.approx((0.0, 0.1, 0.5))


def test_moving_edge_truth_translates_the_exact_coverage():
    """Frame f is the coverage of every triangle moved left and up by f steps: areas kept, centroids moved."""
    size = (64, 48)
    frames = sh.edge_truths(size, frames=3)
    assert frames.shape == (3, 48, 64, 3)
    _world, px, _colour = triangle_shapes(size)[2]  # the large triangle, far from the image border
    ys, xs = np.mgrid[0:48, 0:64] + 0.5
    for f in range(3):
        cov = truth.polygon_coverage(px - f * np.array(sh.EDGE_STEP_PX), size)
        (ax, ay), (bx, by) = px[1] - px[0], px[2] - px[0]
        area = 0.5 * abs(ax * by - ay * bx)
        assert cov.sum() == pytest.approx(area, abs=1e-9)
        centroid = np.array([(cov * xs).sum(), (cov * ys).sum()]) / cov.sum()
        expected = px.mean(axis=0) - f * np.array(sh.EDGE_STEP_PX)
        assert np.abs(centroid - expected).max() < 0.02  # pixel-centre quadrature of a linear function
    assert np.abs(frames[1] - frames[0]).max() > 0.05  # the edges did move
    # The frames themselves: (image - background) is a sum of coverages times constants, so its weighted centroid
    # moves exactly by the step (every shape stays inside the image), left and up.
    from wgpurender.bench.accuracy_analytic import BACKGROUND

    weight = (frames - np.asarray(BACKGROUND)).sum(axis=-1)
    centres = np.array([[(w * xs).sum() / w.sum(), (w * ys).sum() / w.sum()] for w in weight])
    np.testing.assert_allclose(centres[1:] - centres[0], -np.outer([1, 2], sh.EDGE_STEP_PX), atol=0.01)


def test_edge_offset_moves_the_image_by_the_step():
    """One pixel is 2/h world units on the triangles' plane (accuracy_analytic._to_world)."""
    x, y, z = sh.edge_offset(2, (64, 48))
    assert (x, y, z) == pytest.approx((2 * sh.EDGE_STEP_PX[0] * 2 / 48, -2 * sh.EDGE_STEP_PX[1] * 2 / 48, 0.0))


def test_ground_offset_moves_along_the_ground_toward_the_target():
    x, y, z = sh.ground_offset(3)
    assert y == 0.0 and z < 0.0  # the target is at -z from the eye
    assert np.hypot(x, z) == pytest.approx(3 * sh.GROUND_STEP)


def test_moving_ground_truth_of_a_constant_texture_is_constant(monkeypatch):
    monkeypatch.setattr(sh, "ground_texture", lambda n: np.full((n, n, 4), 128, np.uint8))
    frames = sh.ground_truths((16, 12), frames=2, n_sub=2)
    assert np.ptp(frames) < 1e-12


def test_the_truths_do_not_import_the_renderer():
    """The truths are numpy only: accuracy_truth imports nothing of wgpurender, and nothing of wgpu."""
    tree = ast.parse(Path(truth.__file__).read_text())
    names = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
    names += [n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module]
    assert names and not [n for n in names if n.startswith(("wgpurender", "wgpu"))]


@pytest.fixture(scope="module")
def measured(ctx, tmp_path_factory):
    """One small run (64x48, 5 frames): about 10 s on lavapipe."""
    rows = sh.run_shimmer(ctx, tmp_path_factory.mktemp("shimmer"), (64, 48), frames=5, progress=lambda _t: None)
    return {(r.section, r.setting): r for r in rows}


def test_trilinear_shimmers_less_than_nearest_and_bilinear_on_the_minified_plane(measured):
    """lavapipe 96x72, 6 frames: nearest 0.207, linear 0.108, trilinear 0.022 (docs/accuracy.md)."""
    tri = measured["minified plane", "trilinear"].shimmer
    assert tri < 0.5 * measured["minified plane", "linear"].shimmer
    assert tri < 0.5 * measured["minified plane", "nearest"].shimmer


def test_msaa_crawls_less_than_no_anti_aliasing_on_edges(measured):
    """lavapipe 96x72, 6 frames: none 0.0128, MSAA 4x 0.0054."""
    assert measured["edges", "msaa4"].shimmer < 0.7 * measured["edges", "none"].shimmer
    assert measured["edges", "none"].truth_change > 0.0  # the truth moved: there was motion to follow


def test_shifted_moves_eye_and_target_together():
    from wgpurender.core.scene.model import Camera

    cam = Camera(eye=(0.0, 2.0, 0.0), target=(0.0, 0.0, -2.5))
    moved = sh.shifted(cam, (0.5, 0.0, -1.0))
    assert moved.eye == pytest.approx((0.5, 2.0, -1.0)) and moved.target == pytest.approx((0.5, 0.0, -3.5))
    assert moved.fov_y == cam.fov_y
