"""Scenes drawn with image-based lighting ([environment], core/course/ibl_maps.py, shaders_*/ibl_shading.*): the
mirror sphere reflects the sky where the camera and the sphere say it must, a rough dielectric shows the float64
integral of the BRDF over the sky, both paths agree exactly, the GPU compute maps agree with the float64 maps, an
environment without a PBR material builds nothing, and bad .hdr files are one line each."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pbr_reference as ref
import pytest
from shading_model import srgb_decode

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "assets" / "scenes" / "metal_rough_spheres_ibl.toml"
GRID, RADIUS = 5, 0.42  # assets/make_assets.py: spacing 1, z = 0; row 0 metallic 0 (bottom), col 0 roughness 0


@pytest.fixture(scope="module")
def rendered():
    from wgpurender.core.scene import load_scene
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene import render_scene_file

    scene = load_scene(SCENE)
    raw = render_scene_reference(SCENE)
    wgpu = render_scene_file(SCENE, ctx=get_context(), frames=1, knobs={"post_path": "fragment"}).pixels
    return scene, raw[..., :3], wgpu[..., :3]


def sphere_hits(scene, row: int, col: int):
    """Per pixel: the ray's hit on sphere (row, col) (analytic), its unit normal and view vector, and a mask."""
    rays = ref.pixel_rays(scene.render.size, scene.camera.fov_y)  # the camera looks down -z from its eye
    eye = np.asarray(scene.camera.eye, np.float64)
    centre = np.array([col - (GRID - 1) / 2, row - (GRID - 1) / 2, 0.0])
    oc = eye - centre
    b = rays @ oc
    disc = b * b - (oc @ oc - RADIUS * RADIUS)
    t = -b - np.sqrt(np.maximum(disc, 0))
    n = ref.unit(eye + t[..., None] * rays - centre)
    v = -rays
    # well inside the silhouette: the tessellated sphere's normals are close to the analytic ones there
    inside = disc > (0.6 * RADIUS) ** 2
    return n, v, inside


def base_colour() -> np.ndarray:
    import sys

    sys.path.insert(0, str(ROOT / "assets"))
    from make_assets import SPHERE_BASE

    return np.asarray(SPHERE_BASE[:3], np.float64)


def test_both_paths_draw_the_same_image(rendered):
    _, raw, wgpu = rendered
    assert np.array_equal(raw, wgpu)


def test_the_roughness_zero_metal_mirrors_the_sky(rendered):
    """Pixel = L_env(r) F(n.v) with r the reflection of the view about the analytic normal (Schlick F, f0 = the
    base colour). Tolerance from float64: the smallest and largest L_env F over directions within DELTA of r (the
    prefiltered map's 64x32 texels are 5.6 degrees wide, the sphere's 64x32 facets 5.6 degrees too), plus 1/255."""
    from wgpurender.core.course.environment import sky
    from wgpurender.core.course.ibl_maps import lookup

    scene, raw, _ = rendered
    n, v, inside = sphere_hits(scene, GRID - 1, 0)
    n, v = n[inside], v[inside]
    n_dot_v = np.clip(np.sum(n * v, -1), 0, 1)
    r = 2 * n_dot_v[:, None] * n - v
    env = sky().astype(np.float64)
    base = base_colour()
    fresnel = base + (1 - base) * ((1 - n_dot_v) ** 5)[:, None]
    delta = np.radians(6.0)
    turned = [ref.unit(r + delta * np.asarray(d)) for d in
              [(0, 0, 0), (1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]]
    values = np.stack([lookup(env, d) * fresnel for d in turned])
    lo, hi = values.min(0) - 1 / 255, values.max(0) + 1 / 255
    got = srgb_decode(raw[inside] / 255.0)
    ok = np.all((got >= np.clip(lo, 0, 1) - 1e-6) & (got <= np.clip(hi, 0, 1) + 1e-6), axis=-1)
    assert ok.mean() > 0.97, ok.mean()
    # and it is a mirror: the sky above the horizon and the ground below differ on the sphere by the same rows
    up = r[:, 1] > 0.2
    assert got[up].mean() > 3 * got[r[:, 1] < -0.2].mean()


def test_a_rough_dielectric_shows_the_float64_integral_over_the_sky(rendered):
    """Roughness 1, metallic 0 (bottom right): the pixel against sum over sky texels of f(l, v) L omega n.l in
    float64 (tests/pbr_reference.py's BRDF), mostly the diffuse term base E(n) / pi. Tolerance: the split sum's
    error on this sky measured by bench accuracy (2.1% mean relative at 256 samples, docs/accuracy.md), plus the
    irradiance map's nearest 11-degree texel and the sphere's facets: 8% per pixel (measured up to 6.5%), plus
    1/255."""
    from wgpurender.core.course.environment import sky, texel_directions

    scene, raw, _ = rendered
    n, v, inside = sphere_hits(scene, 0, GRID - 1)
    pick = np.flatnonzero(inside.reshape(-1))[::37]
    n, v = n.reshape(-1, 3)[pick], v.reshape(-1, 3)[pick]
    env = sky().astype(np.float64)
    dirs, omega = texel_directions(env.shape[1], env.shape[0])
    dirs, omega, radiance = dirs.reshape(-1, 3), omega.reshape(-1), env.reshape(-1, 3)
    base = base_colour()
    truth = np.array([(ref.radiance(nn[None], dirs, vv[None], base, 0.0, 1.0) / np.pi * radiance
                       * omega[:, None]).sum(0) for nn, vv in zip(n, v, strict=True)])
    got = srgb_decode(raw.reshape(-1, 3)[pick] / 255.0)
    assert np.all(np.abs(got - truth) <= 0.08 * truth + 1 / 255), np.abs(got - truth).max()


def test_gpu_compute_maps_match_the_float64_maps():
    """wgpu_path/scene/ibl.py's compute passes against core/course/ibl_maps.py on the same sky and samples:
    float32 against float64 sums (relative 1e-4 for the irradiance and the table); the prefiltered levels above
    the mirror within 1% mean (a sample on a texel edge may pick the neighbour); level 0's texel centres sit on
    the 128x64 sky's texel edges, so each takes one of its two neighbours."""
    from wgpurender.core.course import ibl_maps
    from wgpurender.core.course.environment import sky
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene.ibl import make_maps

    env = sky()
    gpu = make_maps(get_context(), env, 64)
    cpu = ibl_maps.make_arrays(env, 64)
    assert np.allclose(gpu.irradiance, cpu.irradiance, rtol=1e-4, atol=1e-6)
    assert np.allclose(gpu.lut, cpu.lut, rtol=1e-3, atol=1e-4)
    for k in range(1, ibl_maps.LEVELS):
        diff = np.abs(gpu.prefiltered[k] - cpu.prefiltered[k])
        assert diff.mean() < 0.01 * cpu.prefiltered[k].mean(), k
    w = env.shape[1]
    left = np.roll(env, 1, axis=1)[::2, ::2].astype(np.float64)
    right = env[::2, ::2].astype(np.float64)
    assert w == 2 * ibl_maps.PREFILTER_SIZE[0]
    near = np.minimum(np.abs(gpu.prefiltered[0] - left), np.abs(gpu.prefiltered[0] - right)).max(-1)
    assert np.mean(near < 1e-3 * np.maximum(right.max(-1), 1)) > 0.6


def test_an_environment_without_pbr_materials_builds_no_ibl(tmp_path):
    from wgpurender.core.plan import build_plan
    from wgpurender.core.scene import load_scene

    (tmp_path / "cube.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "s.toml").write_text('[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\n[[models]]\npath = "cube.obj"\n'
                                     '[[lights]]\ntype = "directional"\ndirection = [0, 0, -1]\n'
                                     '[environment]\nprocedural = "sky"\n')
    plan = build_plan(load_scene(tmp_path / "s.toml"))
    assert not plan.uses_ibl
    assert not any("ibl" in name for name, _ in plan.buffers)
    assert all("ibl" not in v.flags for v in plan.variants)
    assert any(what == "image-based lighting maps" for what, _ in plan.absent)


def test_the_ibl_scene_plans_one_maps_buffer_with_its_bytes():
    from wgpurender.core.course import ibl_maps
    from wgpurender.core.plan import build_plan
    from wgpurender.core.scene import load_scene

    plan = build_plan(load_scene(SCENE))
    rows = [what for name, what in plan.buffers if name == "scene-ibl"]
    assert len(rows) == 1 and f"({16 * (32 * 16 + 5 * 64 * 32 + 32 * 32)} bytes" in rows[0]
    assert ibl_maps.packed_bytes() == 16 * (32 * 16 + 5 * 64 * 32 + 32 * 32)
    assert all("ibl" in v.flags for v in plan.variants)
