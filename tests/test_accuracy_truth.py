"""The analytic ground truths of ``bench accuracy --truth analytic`` (wgpurender/bench/accuracy_truth.py).

The truths are checked against closed forms written here (areas, a constant texture, a checker's mean), and
one small GPU run checks that the renderer's anti-aliasing converges to the truth: the scene and its exact
image line up to a fraction of a pixel, and more samples give less error.
"""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.bench import accuracy_truth as truth
from wgpurender.bench.accuracy_analytic import write_triangles_scene
from wgpurender.bench.accuracy_downsample import linear_from_srgb8, srgb8_from_linear
from wgpurender.bench.accuracy_knobs import Settings
from wgpurender.bench.accuracy_run import Timed
from wgpurender.core.scene import load_scene
from wgpurender.core.verdict.compare import compare_images


def _shoelace(tri: np.ndarray) -> float:
    (ax, ay), (bx, by), (cx, cy) = tri
    return 0.5 * abs((bx - ax) * (cy - ay) - (cx - ax) * (by - ay))


def test_coverage_sums_to_the_triangle_area():
    rng = np.random.default_rng(12)
    for _ in range(20):
        tri = rng.uniform(0.0, [32.0, 24.0], size=(3, 2))
        cov = truth.polygon_coverage(tri, (32, 24))
        assert cov.min() >= 0.0 and cov.max() <= 1.0 + 1e-12
        assert cov.sum() == pytest.approx(_shoelace(tri), abs=1e-9)


def test_coverage_of_a_pixel_aligned_right_triangle():
    """Legs along pixel edges from (2, 2) to (10, 2) and (2, 10): pixels below the diagonal are full, the
    diagonal's pixels half covered, the rest empty."""
    cov = truth.polygon_coverage(np.array([[2.0, 2.0], [10.0, 2.0], [2.0, 10.0]]), (12, 12))
    ys, xs = np.mgrid[0:12, 0:12]
    inside = (xs >= 2) & (ys >= 2)
    s = (xs - 2) + (ys - 2)  # pixel (x, y) spans x + y in [s, s + 2] relative to the corner
    expected = np.where(inside & (s <= 6), 1.0, 0.0) + np.where(inside & (s == 7), 0.5, 0.0)
    np.testing.assert_allclose(cov, expected, atol=1e-12)


def test_footprint_of_a_constant_and_of_a_fine_checker():
    eye, target = (0.0, 2.0, 0.0), (0.0, 0.0, -2.5)
    constant = np.full((4, 4, 3), 0.3)
    out = truth.footprint_average(constant, eye, target, 45.0, (16, 12), 1.0, n=4)
    np.testing.assert_allclose(out, 0.3, atol=1e-12)
    checker = np.zeros((2, 2, 1))
    checker[0, 0] = checker[1, 1] = 1.0
    far = truth.footprint_average(checker, eye, target, 45.0, (16, 12), 40.0, n=16)[:3]
    assert np.abs(far - 0.5).max() < 0.05  # far away, a pixel covers many checker cells: their mean


def test_anti_aliasing_converges_to_the_analytic_coverage(ctx, tmp_path):
    """80x60, flat triangles: against the exact image, 4x supersampling reaches more than 34 dB PSNR and beats
    4x MSAA, which beats no anti-aliasing (lavapipe: 37.9, 32.8 and 23.6 dB). A truth misplaced by half a pixel
    (25.6 dB), or a supersampling resolve that averaged encoded values (30.3 dB), fails."""
    size = (80, 60)
    path, exact = write_triangles_scene(tmp_path, size, fxaa=False)
    scene = load_scene(path)
    truth8 = srgb8_from_linear(exact)
    errors = {}
    settings_of = {"none": Settings(msaa=1), "msaa4": Settings(msaa=4), "ssaa4": Settings(msaa=1, ss=4)}
    for label, settings in settings_of.items():
        t = Timed(ctx, scene, settings, size, ("msaa", "ss"))
        t.run(1)
        t.read()
        errors[label] = compare_images(truth8, t.pixels[..., :3], with_flip=False).psnr
        mae = np.abs(linear_from_srgb8(t.pixels)[..., :3] - exact).mean()
        assert mae < 0.02, f"{label}: mean error {mae:.4f} against the exact coverage image"
    assert errors["ssaa4"] > 34.0, errors
    assert errors["ssaa4"] > errors["msaa4"] > errors["none"], errors
