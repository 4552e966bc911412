"""Image-based lighting maps made on the GPU (wgpu_path/scene/ibl.py, shaders_wgsl/ibl.wgsl) against answers worked out
here: a uniform environment, one bright texel, the split-sum BRDF integrals by plain quadrature, and the bench
section's error falling with the sample count."""

from __future__ import annotations

import numpy as np
import pytest

W, H = 32, 16  # a small environment keeps the GPU sums quick on a CPU adapter


def equirect_direction(u, v) -> np.ndarray:
    """The documented layout (core/course/environment.py): u -> longitude, v -> polar angle from +y."""
    phi, theta = (u - 0.5) * 2 * np.pi, v * np.pi
    return np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], axis=-1)


@pytest.fixture(scope="module")
def gpu():
    from wgpurender.wgpu_path.device.context import get_context

    return get_context()


def path_maps(path: str):
    """make_maps(environment, samples, ...) of one path's compute passes (wgpu: ibl.wgsl, raw: ibl.comp)."""
    if path == "wgpu":
        from wgpurender.wgpu_path.device.context import get_context
        from wgpurender.wgpu_path.scene.ibl import make_maps

        return lambda *args, **kw: make_maps(get_context(), *args, **kw)
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.scene.ibl import make_maps

    return lambda *args, **kw: make_maps(get_vulkan(), *args, **kw)


def test_a_uniform_environment_gives_its_radiance_everywhere(gpu):
    """Radiance c from every direction: E / pi = c for every normal, and every prefiltered level is c."""
    from wgpurender.wgpu_path.scene.ibl import make_maps

    c = np.array([0.5, 0.25, 2.0], np.float32)
    maps = make_maps(gpu, np.broadcast_to(c, (H, W, 3)).copy(), samples=32)
    assert np.allclose(maps.irradiance, c, rtol=2e-3)
    assert np.allclose(maps.prefiltered, c, rtol=1e-5)


def test_one_bright_texel_lights_by_its_cosine_and_solid_angle(gpu):
    """Only texel (x, y) is bright (L): E(n) / pi = L max(n.l, 0) omega / pi, l its centre's direction and omega
    = (2 pi / W)(cos theta0 - cos theta1) its solid angle."""
    from wgpurender.wgpu_path.scene.ibl import make_maps

    x, y, radiance = 5, 4, 100.0
    env = np.zeros((H, W, 3), np.float32)
    env[y, x] = radiance
    maps = make_maps(gpu, env, samples=16, irradiance_size=(16, 8))
    l_dir = equirect_direction((x + 0.5) / W, (y + 0.5) / H)
    omega = 2 * np.pi / W * (np.cos(y / H * np.pi) - np.cos((y + 1) / H * np.pi))
    ih, iw = maps.irradiance.shape[:2]
    vv, uu = np.meshgrid((np.arange(ih) + 0.5) / ih, (np.arange(iw) + 0.5) / iw, indexing="ij")
    n = equirect_direction(uu, vv)
    want = radiance * np.clip(n @ l_dir, 0, None) * omega / np.pi
    assert np.allclose(maps.irradiance[..., 0], want, atol=1e-4 * radiance)
    assert want.max() > 0.5 and (want == 0).mean() > 0.3  # lit and unlit normals both checked


def test_roughness_zero_prefilter_is_the_mirror_lookup(gpu):
    """Level 0 (roughness 0): every sample is the mirror direction n, so the texel shows the environment there
    (random texels: a layout turned about any axis shows)."""
    from wgpurender.wgpu_path.scene.ibl import make_maps

    env = np.random.default_rng(30).random((H, W, 3)).astype(np.float32)
    maps = make_maps(gpu, env, samples=8, prefilter_size=(W, H))
    assert np.allclose(maps.prefiltered[0], env, rtol=1e-5)


def band_solid_angles(width: int, height: int) -> np.ndarray:
    """(height,) solid angle of one texel of each row: (2 pi / width)(cos theta0 - cos theta1)."""
    edges = np.arange(height + 1) / height * np.pi
    return 2 * np.pi / width * (np.cos(edges[:-1]) - np.cos(edges[1:]))


@pytest.mark.parametrize("path", ["wgpu", "raw"])
def test_the_mirror_level_of_a_half_size_map_is_the_mean_of_each_2x2_block(path):
    """Level 0 at half the environment's size: each texel covers a 2x2 block exactly, so it is the block's
    solid-angle-weighted mean (random texels: the four differ). Before, GGX samples at roughness 0 sat on the
    block's corner and float rounding chose the blend (on an H100, 57% of the sky's texels near a neighbour)."""
    env = np.random.default_rng(7).random((H, W, 3)).astype(np.float32)
    maps = path_maps(path)(env, samples=64, prefilter_size=(W // 2, H // 2))
    omega = band_solid_angles(W, H)[:, None, None] * np.ones((1, W, 1))
    blocks = (env * omega).reshape(H // 2, 2, W // 2, 2, 3).sum((1, 3))
    want = blocks / omega.reshape(H // 2, 2, W // 2, 2, 1).sum((1, 3))
    assert np.allclose(maps.prefiltered[0], want, rtol=1e-4)


@pytest.mark.parametrize("path", ["wgpu", "raw"])
def test_the_mirror_level_of_a_map_larger_than_the_environment_is_the_texel_under_each_centre(path):
    env = np.random.default_rng(8).random((2, 4, 3)).astype(np.float32)
    maps = path_maps(path)(env, samples=8, prefilter_size=(8, 4))
    assert np.allclose(maps.prefiltered[0], env.repeat(2, 0).repeat(2, 1), rtol=1e-6)


@pytest.mark.parametrize("path", ["wgpu", "raw"])
def test_the_mirror_level_at_sizes_that_do_not_divide_is_the_float64_one(path):
    """A 10x5 environment on a 6x3 and a 13x7 map: blocks of one or two texels, uneven, and texels with none
    (then the texel under the centre), against core/course/ibl_maps.mirror_level in float64."""
    from wgpurender.core.course.ibl_maps import mirror_level

    env = np.random.default_rng(9).random((5, 10, 3)).astype(np.float32)
    for size in ((6, 3), (13, 7)):
        maps = path_maps(path)(env, samples=8, prefilter_size=size)
        assert np.allclose(maps.prefiltered[0], mirror_level(env.astype(np.float64), size), rtol=1e-5), size


def split_sum_integrals(n_dot_v: float, roughness: float, steps: int = 600) -> tuple[float, float]:
    """A = integral of D V (1 - Fc) n.l, B = integral of D V Fc n.l over the hemisphere (Fc = (1 - v.h)^5), by the
    midpoint rule in (theta, phi): the split sum's f0 A + B = integral of f n.l for Schlick's F."""
    a2 = roughness**4
    theta = (np.arange(steps) + 0.5) / steps * np.pi / 2
    phi = (np.arange(2 * steps) + 0.5) / (2 * steps) * 2 * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    l_dir = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)
    v = np.array([np.sqrt(1 - n_dot_v**2), 0.0, n_dot_v])
    h = l_dir + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    nl, nh, vh = l_dir[..., 2], h[..., 2], h @ v
    d = a2 / (np.pi * (nh**2 * (a2 - 1) + 1) ** 2)
    vis = 0.5 / (nl * np.sqrt(n_dot_v**2 * (1 - a2) + a2) + n_dot_v * np.sqrt(nl**2 * (1 - a2) + a2))
    fc = (1 - vh) ** 5
    weight = d * vis * nl * np.sin(t) * (np.pi / 2 / steps) * (2 * np.pi / (2 * steps))
    return float((weight * (1 - fc)).sum()), float((weight * fc).sum())


@pytest.mark.parametrize("cell", [(4, 12), (16, 16), (28, 20), (12, 28), (30, 31)])
def test_brdf_lut_matches_the_integrals(gpu, cell):
    """LUT cell (column n.v, row roughness) at cell centres, 1024 samples, against split_sum_integrals."""
    from wgpurender.wgpu_path.scene.ibl import make_maps

    maps = make_maps(gpu, np.zeros((2, 4, 3), np.float32), samples=1024, irradiance_size=(1, 1),
                     prefilter_size=(1, 1))
    col, row = cell
    n = maps.lut.shape[0]
    a, b = split_sum_integrals((col + 0.5) / n, (row + 0.5) / n)
    assert maps.lut[row, col] == pytest.approx([a, b], abs=0.015)


def test_bench_section_error_falls_with_the_sample_count(gpu):
    """The bench's rows on a small sky: one per sample count, the error with the most samples below the fewest's
    and within 15% of the mean radiance (what remains is the split sum's own approximation), times recorded."""
    from wgpurender.bench.accuracy_analytic import TruthRow
    from wgpurender.bench.accuracy_ibl import SAMPLE_COUNTS, run_ibl
    from wgpurender.core.course.environment import sky

    both = run_ibl(gpu, 1, TruthRow, environment=sky(W, H))
    assert [r.setting for r in both] == [s for n in SAMPLE_COUNTS
                                         for s in (f"{n} samples", f"{n} samples, float64 CPU (the check)")]
    for rows in (both[0::2], both[1::2]):  # the GPU's compute maps, then the float64 maps scenes draw
        assert rows[-1].linear_mae < rows[0].linear_mae
        relative = float(rows[-1].note.split()[2].rstrip("%;")) / 100
        assert relative < 0.15, rows[-1].note
        assert all(r.m.wall.median > 0 for r in rows)
    for gpu_row, cpu_row in zip(both[0::2], both[1::2], strict=True):  # the same algorithm: the same error
        assert abs(gpu_row.linear_mae - cpu_row.linear_mae) < 0.1 * cpu_row.linear_mae


def test_split_sum_of_a_metal_under_a_uniform_sky_is_its_directional_albedo(gpu):
    """Under a uniform sky c the prefiltered map is c everywhere, so a metal's split sum c (f0 A + B) is exact up to
    the table's resolution: it must match the float64 integral of f n.l c (accuracy_ibl.truth) at every normal
    (within 1% of the brightest; at roughness 1 the table's own sampling noise at grazing n.v is larger)."""
    from wgpurender.bench.accuracy_ibl import sphere_normals, split_sum, truth
    from wgpurender.wgpu_path.scene.ibl import make_maps

    env = np.ones((H, W, 3), np.float32)
    maps = make_maps(gpu, env, samples=1024)
    normals = sphere_normals()
    for roughness in (0.5, 0.75):  # (a narrower lobe needs a finer sky than the truth sums here)
        exact = truth(env, normals, 1.0, roughness)
        got = split_sum(maps, normals, 1.0, roughness)
        assert np.abs(got - exact).max() < 0.01 * exact.max(), (roughness, np.abs(got - exact).max(), exact.max())
