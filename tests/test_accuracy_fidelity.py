"""The two float64 truths added to ``bench accuracy --truth analytic`` (wgpurender/bench/accuracy_fidelity.py) and
its Pareto marking, checked against closed forms written here; then one small GPU run of each knob."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from wgpurender.bench import accuracy_fidelity as fidelity


def test_the_box_pyramid_of_a_checker_is_its_mean_below_the_base():
    checker = np.zeros((8, 8, 3))
    checker[::2, ::2] = checker[1::2, 1::2] = 1.0
    levels = fidelity.box_pyramid(checker)
    assert [lv.shape[:2] for lv in levels] == [(8, 8), (4, 4), (2, 2), (1, 1)]
    for lv in levels[1:]:
        assert np.allclose(lv, 0.5)


def test_the_box_pyramid_averages_2x2_blocks():
    ramp = np.arange(16, dtype=np.float64).reshape(4, 4, 1)
    assert np.allclose(fidelity.box_pyramid(ramp)[1][..., 0], [[2.5, 4.5], [10.5, 12.5]])


def test_plane_truth_at_a_pixel_centre_is_the_documented_model():
    """One pixel worked by hand: scene.wgsl's L = ambient*albedo + E n.l (albedo + 0.04 (s+8)/8 (n.h)^s)."""
    size = (4, 2)
    got = fidelity.plane_truth(size)[0, 2]  # pixel (2, 0): centre at (2.5, 0.5)
    d = 1 / np.tan(np.radians(22.5))
    p = np.array([(2 * 2.5 / 4 - 1) * 2, 1 - 2 * 0.5 / 2, 0.0])  # x = 0.5, y = 0.5
    light = np.array([0.3, 0.2, 1.0]) - p
    dist2 = light @ light
    l_dir = light / np.sqrt(dist2)
    v = np.array([0, 0, d]) - p
    v = v / np.linalg.norm(v)
    h = (l_dir + v) / np.linalg.norm(l_dir + v)
    s = 2 / 0.5**4 - 2  # 30
    albedo = np.array([0.6, 0.5, 0.4])
    want = np.array([0.03, 0.03, 0.035]) * albedo + 1.5 / dist2 * l_dir[2] * (albedo + 0.04 * (s + 8) / 8 * h[2] ** s)
    assert np.allclose(got, want, rtol=1e-12)


def _row(section, time_ms, mae):
    m = SimpleNamespace(gpu=None, wall=SimpleNamespace(median=time_ms))
    return SimpleNamespace(section=section, linear_mae=mae, m=m, pareto=False,
                           time_ms=lambda: time_ms)


def test_pareto_is_marked_within_each_knob():
    from wgpurender.bench.accuracy_analytic import mark_pareto

    rows = [_row("a", 1.0, 0.5), _row("a", 2.0, 0.1), _row("a", 3.0, 0.2), _row("b", 5.0, 0.9), _row("b", 1.0, 0.9)]
    mark_pareto(rows)
    assert [r.pareto for r in rows] == [True, True, False, False, True]


def test_the_gpu_mip_chain_is_averaged_in_linear_light(ctx):
    """The project's chain is within 1/255-ish of the float64 pyramid; averaging the stored bytes is far off."""
    rows = fidelity.run_mip_chain(ctx, 1, lambda *a: SimpleNamespace(setting=a[1], mae=a[5], psnr=a[4]))
    mae = {r.setting: r.mae for r in rows}
    assert mae["linear light"] < 0.005 < 0.05 < mae["stored bytes"]
    assert mae["decimate"] > mae["stored bytes"] > mae["linear light"]


def test_shading_matches_float64_lighting_in_every_format(ctx, tmp_path):
    from wgpurender.bench.accuracy_analytic import _score, _timed

    rows = fidelity.run_shading(ctx, tmp_path, (48, 36), 1, 0, _timed, _score)
    assert [r.setting for r in rows] == list(fidelity.SHADING_FORMATS)
    for r in rows:  # 8-bit output quantisation bounds the error: about half an sRGB step in linear light
        assert r.linear_mae < 0.004 and r.psnr > 50, (r.setting, r.linear_mae, r.psnr)
