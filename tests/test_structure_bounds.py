"""The size-free measures and size classes of the implementation bounds (issue 32, item 6), on images built
here with known answers (core/verdict/structure.py, tolerances.Tolerance.at_size / structure_exceeded)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from dropped_effects import post_blocks, without_post

from wgpurender.core.scene import load_scene
from wgpurender.core.verdict.structure import RINGS, Structure, detail_change, radial_shift, ring_index, structure
from wgpurender.core.verdict.tolerances import Tolerance, Uncalibrated, calibrate_structure
from wgpurender.implementations import scene_files


def gray(value: int, h: int = 60, w: int = 80) -> np.ndarray:
    return np.full((h, w, 4), value, np.uint8)


def test_rings_run_from_the_centre_to_the_corners():
    rings = ring_index(60, 80)
    assert rings[30, 40] == 0 and rings[0, 0] == rings[59, 79] == RINGS - 1
    assert set(np.unique(rings)) == set(range(RINGS))


def test_a_darker_outer_ring_is_its_median_shift():
    a = gray(100)
    b = a.copy()
    b[ring_index(60, 80) == RINGS - 1, :3] = 93  # the corners 7/255 darker: a vignette
    assert radial_shift(a, b) == 7.0


def test_sign_balanced_differences_have_no_radial_shift():
    a = gray(100)
    b = a.copy()
    b[::2, ::2, :3] += 9  # a quarter of the pixels up, a quarter down (less): median 0, mean 1.75
    b[1::2, 1::2, :3] -= 2
    assert radial_shift(a, b) == 0.0


def test_black_pixels_are_left_out():
    """Only the reference's lit pixels count: a vignette cannot change black, so black must not outvote it."""
    a = gray(0)
    b = a.copy()
    b[..., :3] = 6
    assert radial_shift(a, b) == 0.0
    a[ring_index(60, 80) == RINGS - 1, :3] = 50
    b[ring_index(60, 80) == RINGS - 1, :3] = 44
    assert radial_shift(a, b) == 6.0


def test_a_ring_with_too_few_lit_pixels_is_left_out():
    a, b = gray(0), gray(0)
    a[0, 0, :3], b[0, 0, :3] = 100, 50  # 1 lit pixel of 4800: under 1% of the image
    assert radial_shift(a, b) == 0.0
    a[:6, :8, :3], b[:6, :8, :3] = 100, 50  # 48 pixels = 1%
    assert radial_shift(a, b) == 50.0


def stripes(low: int, high: int, h: int = 60, w: int = 80) -> np.ndarray:
    image = gray(low, h, w)
    image[:, ::2, :3] = high
    return image


def test_detail_is_the_log2_gradient_ratio_on_edges():
    """Columns alternating 0 and 200 (each 3x3 spans 200 > EDGE: all edge pixels): every horizontal step is
    200/255, vertical 0, so the mean gradient is 200; halving the contrast to 50..150 reads log2(101 / 201),
    flattening log2(1 / 201)."""
    assert detail_change(stripes(0, 200), stripes(50, 150)) == pytest.approx(math.log2(101 / 201))
    assert detail_change(stripes(0, 200), gray(100)) == pytest.approx(-math.log2(201))
    assert detail_change(stripes(0, 200), stripes(0, 255)) == pytest.approx(math.log2(256 / 201))  # sharpened
    assert structure(stripes(0, 200), stripes(0, 200)) == Structure(0.0, 0.0)


def test_detail_ignores_contrast_away_from_edges():
    """Only the reference's edges count: texture-level contrast (a 3x3 span up to EDGE) may change freely, and
    a reference without edges reads 0."""
    assert detail_change(stripes(50, 150), gray(100)) == 0.0  # span 100: no edges
    a = stripes(0, 200)
    a[:, 40:, :3] = 100  # right half flat
    b = a.copy()
    b[:, 44::2, :3] = 140  # texture-level stripes, away from the left half's edges
    assert detail_change(a, b) == 0.0
    b[:, :40:2, :3] = 100  # the edges' contrast halved
    assert detail_change(a, b) < -0.5


TOL = Tolerance("final", "browser", 65, 0.85, 0.052, "m", "b", False, radial=1.0, detail=0.15, size="160x120",
                sizes=(("320x240", {"max_abs": 77, "changed": 0.81}), ("640x480", {"max_abs": 86})))


@pytest.mark.parametrize(("size", "max_abs", "changed", "name"), [
    ((160, 120), 65, 0.85, "160x120"), ((96, 72), 65, 0.85, "160x120"), ((161, 120), 77, 0.81, "320x240"),
    ((320, 240), 77, 0.81, "320x240"), ((400, 300), 86, 0.85, "640x480"), ((640, 480), 86, 0.85, "640x480")])
def test_an_image_takes_the_smallest_size_class_that_holds_it(size, max_abs, changed, name):
    tol = TOL.at_size(*size)
    assert (tol.max_abs, tol.changed, tol.flip_mean, tol.size) == (max_abs, changed, 0.052, name)
    assert (tol.radial, tol.detail) == (1.0, 0.15)


def test_above_the_largest_class_is_uncalibrated():
    with pytest.raises(Uncalibrated, match="calibrated up to 640x480, not 641x480"):
        TOL.at_size(641, 480)
    plain = Tolerance("x", "same device", 1, 1.0, 0.01, "m", "b", False)
    assert plain.at_size(4000, 3000) is plain


def test_each_size_free_bound_names_what_it_caught():
    assert TOL.structure_exceeded(Structure(1.0, 0.15)) == []
    assert TOL.structure_exceeded(Structure(1.0, -0.15)) == []
    radial, = TOL.structure_exceeded(Structure(3.0, 0.0))
    assert radial.startswith("radial shift 3/255 > 1/255")
    detail, = TOL.structure_exceeded(Structure(0.0, -0.2))
    assert detail.startswith("detail change -0.200 beyond +-0.15")
    assert len(TOL.structure_exceeded(Structure(2.0, 0.2))) == 2
    assert Tolerance("x", "y", 1, 1.0, 0.01, "m", "b", False).structure_exceeded(Structure(99.0, 9.0)) == []


def test_the_size_free_calibration_rule():
    """radial = worst + 1/255; detail = 2 x the worst magnitude, rounded up to 2 figures, at least 0.02."""
    got = calibrate_structure([Structure(0.0, 0.0453), Structure(0.0, -0.0741)], ["160x120", "320x240"])
    assert (got["radial"], got["detail"]) == (1.0, 0.15)
    assert got["structure_measured"] == "radial 0/255, detail 0.0741 (worst of 160x120, 320x240)"
    assert calibrate_structure([Structure(2.0, 0.0001)], ["160x120"])["radial"] == 3.0
    assert calibrate_structure([Structure(0.0, 0.0001)], ["160x120"])["detail"] == 0.02


@pytest.mark.parametrize("name", ["brick", "final", "final_subpass", "retro"])
def test_a_cut_scene_loses_exactly_one_effect(tmp_path, name):
    path = scene_files()[name]
    effects = [step.effect for step in load_scene(path).post]
    assert len(post_blocks(path.read_text())) == len(effects)
    for k in range(len(effects)):
        cut = load_scene(without_post(path, k, tmp_path / f"{name}-{k}.toml"))
        assert [step.effect for step in cut.post] == effects[:k] + effects[k + 1:]
        assert len(cut.models) == len(load_scene(path).models)


def test_the_raw_chain_bound_catches_a_ring_shift():
    """raw vs wgpu-vulkan on a post chain measured radial 0/255 and |detail| <= 0.0003 at 160x120 to 640x480
    (docs/runs/2026-11-27-size-free-bounds): within; a vignette's 3/255 or a lost sharpen is not."""
    from wgpurender.verify import CHAIN_BOUND

    assert CHAIN_BOUND.structure_exceeded(Structure(0.0, 0.0003)) == []
    assert len(CHAIN_BOUND.structure_exceeded(Structure(3.0, -0.5))) == 2
