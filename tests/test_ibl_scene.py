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


def assert_near_the_float64_maps(gpu) -> None:
    """A path's compute maps of sky() at 64 samples against core/course/ibl_maps.py's: float32 against float64
    sums (relative 1e-4 for the irradiance, the table and the mirror level, whose band weights are float32
    cosines); the prefiltered levels above the mirror within 1% mean (a sample on a texel edge may pick the
    neighbour: measured 0.08-0.30% on lavapipe, 0.13-0.49% on an H100, 2026-11-27)."""
    from wgpurender.core.course import ibl_maps
    from wgpurender.core.course.environment import sky

    cpu = ibl_maps.make_arrays(sky(), 64)
    assert np.allclose(gpu.irradiance, cpu.irradiance, rtol=1e-4, atol=1e-6)
    assert np.allclose(gpu.lut, cpu.lut, rtol=1e-3, atol=1e-4)
    assert np.allclose(gpu.prefiltered[0], cpu.prefiltered[0], rtol=1e-4, atol=1e-6)
    for k in range(1, ibl_maps.LEVELS):
        assert np.abs(gpu.prefiltered[k] - cpu.prefiltered[k]).mean() < 0.01 * cpu.prefiltered[k].mean(), k


def test_gpu_compute_maps_match_the_float64_maps():
    """wgpu_path/scene/ibl.py's compute passes against the float64 maps on the same sky and samples."""
    from wgpurender.core.course.environment import sky
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene.ibl import make_maps

    assert_near_the_float64_maps(make_maps(get_context(), sky(), 64))


def test_raw_compute_maps_match_the_float64_maps_and_the_wgpu_path():
    """raw_path/scene/ibl.py (shaders_glsl/ibl.comp) against the float64 maps, and the wgpu path's maps (twins
    operation for operation: the scenes' images rest on it): the prefiltered levels and the table equal; the
    irradiance sums (8192 terms each) within relative 1e-6, as a driver may contract a multiply-add differently in
    the two compiled modules (measured 2026-11-27: equal on lavapipe, 1.8e-7 apart at most on an H100, about one
    float32 ulp; the IBL scene's images stayed equal there)."""
    from wgpurender.core.course.environment import sky
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.scene.ibl import make_maps as raw_maps
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene.ibl import make_maps as wgpu_maps

    raw = raw_maps(get_vulkan(), sky(), 64)
    assert_near_the_float64_maps(raw)
    wgpu = wgpu_maps(get_context(), sky(), 64)
    assert np.allclose(raw.irradiance, wgpu.irradiance, rtol=1e-6, atol=0)
    for name in ("prefiltered", "lut"):
        assert np.array_equal(getattr(raw, name), getattr(wgpu, name)), name


def test_a_scene_draws_the_gpu_maps_on_both_paths(monkeypatch):
    """The buffer each path binds holds its own compute passes' maps, packed (not the float64 ones)."""
    from wgpurender.core.course import ibl_maps
    from wgpurender.core.scene import load_scene
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.scene.ibl import make_maps as raw_maps

    scene = load_scene(SCENE)
    env = ibl_maps.scene_environment(scene.environment)
    assert env.shape == (64, 128, 3) and env.dtype == np.float32
    gpu = ibl_maps.pack(raw_maps(get_vulkan(), env, scene.environment.samples))
    assert gpu.shape == (ibl_maps.packed_rows(), 4)
    assert not np.array_equal(gpu, ibl_maps.scene_maps(scene.environment))  # float32 sums differ in the last bits
    calls = []
    monkeypatch.setattr(ibl_maps, "make_arrays", lambda *a, **k: calls.append(a))  # the float64 maps: unused
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene import render_scene_file

    raw = render_scene_reference(SCENE, size=(32, 24))
    wgpu = render_scene_file(SCENE, size=(32, 24), ctx=get_context(), frames=1, knobs={"post_path": "fragment"})
    assert calls == [] and np.array_equal(raw, wgpu.pixels)


def test_an_environment_without_pbr_materials_builds_no_ibl(tmp_path):
    from wgpurender.core.plan import resolve_plan
    from wgpurender.core.scene import load_scene

    (tmp_path / "cube.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "s.toml").write_text('[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\n[[models]]\npath = "cube.obj"\n'
                                     '[[lights]]\ntype = "directional"\ndirection = [0, 0, -1]\n'
                                     '[environment]\nprocedural = "sky"\n')
    plan = resolve_plan(load_scene(tmp_path / "s.toml"), None)
    assert not plan.uses_ibl
    assert not any("ibl" in name for name, _ in plan.buffers)
    assert all("ibl" not in v.flags for v in plan.variants)
    assert any(what == "image-based lighting maps" for what, _ in plan.absent)


def test_the_ibl_scene_plans_one_maps_buffer_with_its_bytes():
    from wgpurender.core.course import ibl_maps
    from wgpurender.core.plan import resolve_plan
    from wgpurender.core.scene import load_scene

    plan = resolve_plan(load_scene(SCENE), None)
    rows = [what for name, what in plan.buffers if name == "scene-ibl"]
    assert len(rows) == 1 and f"({16 * (32 * 16 + 5 * 64 * 32 + 32 * 32)} bytes" in rows[0]
    assert ibl_maps.packed_bytes() == 16 * (32 * 16 + 5 * 64 * 32 + 32 * 32)
    assert all("ibl" in v.flags for v in plan.variants)


def test_an_hdr_file_round_trips_and_lights_the_scene(tmp_path):
    """A flat .hdr written here (RGBE of known values) reads back within RGBE's step: the exponent is shared, so
    each channel is within 1/256 of the pixel's largest channel (twice, for the rounding on both sides)."""
    from wgpurender.core.files.hdr_io import encode_hdr, load_hdr

    values = np.array([[[0.5, 0.25, 2.0], [40.0, 36.0, 30.0]], [[0.0, 0.0, 0.0], [1e-3, 0.1, 0.01]]])
    (tmp_path / "e.hdr").write_bytes(encode_hdr(values))
    got = load_hdr(tmp_path / "e.hdr")
    assert got.shape == (2, 2, 3)
    assert np.all(np.abs(got - values) <= 2 / 256 * values.max(-1, keepdims=True))


def rle_hdr(width: int, pixel: tuple[int, int, int, int]) -> bytes:
    """One new-style RLE scanline per row: each channel one run of ``width`` (built from the format's text)."""
    line = bytes([2, 2, width >> 8, width & 255])
    for value in pixel:
        rest = width
        while rest:
            n = min(rest, 127)
            line += bytes([128 + n, value])
            rest -= n
    return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X %d\n" % width + line * 2


def test_a_run_length_encoded_hdr_decodes():
    from wgpurender.core.files.hdr_io import decode_hdr

    got = decode_hdr(rle_hdr(300, (128, 64, 32, 129)))
    assert got.shape == (2, 300, 3)
    assert np.allclose(got, np.array([128.5, 64.5, 32.5]) / 256 * 2.0, rtol=1e-6)


@pytest.mark.parametrize("data, says", [
    (b"P6\n1 1\n255\n\0\0\0", "not a Radiance .hdr"),
    (b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\0\0\0\0", "not supported"),
    (b"#?RADIANCE\n\n+Y 1 +X 1\n\0\0\0\0", "resolution line"),
    (b"#?RADIANCE\n\n-Y 2 +X 2\n\0\0\0\0", "truncated"),
    (b"#?RADIANCE\n\n-Y 100000 +X 100000\n", "over the limit"),
    (b"#?RADIANCE\n\n-Y 0 +X 4\n", "at least one"),
    (b"#?RADIANCE\n" + b"X=1\n" * 100, "header longer"),
])
def test_a_bad_hdr_is_one_line_and_exit_2(tmp_path, data, says):
    import subprocess
    import sys

    (tmp_path / "bad.hdr").write_bytes(data)
    (tmp_path / "s.toml").write_text(SCENE.read_text().replace('procedural = "sky"', 'hdr = "bad.hdr"')
                                     .replace("../models/", str(ROOT / "assets" / "models") + "/"))
    run = subprocess.run([sys.executable, "-m", "wgpurender", "render", str(tmp_path / "s.toml"), "-o",
                          str(tmp_path / "o.png")], capture_output=True, text=True, timeout=300)
    assert run.returncode == 2, run.stderr
    assert says in run.stderr and "Traceback" not in run.stderr and len(run.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "o.png").exists()


def test_environment_table_mistakes_are_one_line(tmp_path):
    from wgpurender.core.errors import UserError
    from wgpurender.core.scene import parse_scene

    head = '[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\n[environment]\n'
    for body, says in [('procedural = "sky"\nhdr = "x.hdr"\n', "exactly one"), ("", "exactly one"),
                       ('procedural = "sea"\n', "sky"), ('hdr = "missing.hdr"\n', "not found"),
                       ('procedural = "sky"\nsamples = 100\n', "16, 64, 256, 1024"),
                       ('procedural = "sky"\nintensity = -1\n', "intensity")]:
        with pytest.raises(UserError, match=says):
            parse_scene(head + body, tmp_path / "s.toml")


def test_explain_lists_the_maps_with_why_and_bytes():
    from wgpurender.core.plan import resolve_plan
    from wgpurender.core.scene import load_scene

    text = resolve_plan(load_scene(SCENE), None).explain()
    assert "ibl" in text and "[environment] procedural 'sky'" in text
    assert "scene-ibl: storage: image-based lighting maps" in text and "188416 bytes" in text


def test_a_large_environment_is_averaged_down_keeping_its_power():
    """512x256 -> 256x128: a constant stays itself; a sky bright above the horizon and dark below keeps its
    integral of L over the sphere (the solid-angle weighting) and its horizon row."""
    from wgpurender.core.course.environment import texel_directions
    from wgpurender.core.course.ibl_maps import MAX_ENVIRONMENT, shrink

    big = np.full((256, 512, 3), 0.7)
    assert np.allclose(shrink(big), 0.7) and shrink(big).shape == (128, 256, 3)
    rows = np.linspace(0, 1, 256)[:, None, None] ** 3 * np.ones((1, 512, 3))
    small = shrink(rows, MAX_ENVIRONMENT)
    _, big_omega = texel_directions(512, 256)
    _, small_omega = texel_directions(256, 128)
    assert np.isclose((rows[..., 0] * big_omega).sum(), (small[..., 0] * small_omega).sum(), rtol=1e-12)


def test_intensity_scales_the_environment():
    from wgpurender.core.course.environment import sky
    from wgpurender.core.scene.environment_block import Environment

    assert np.allclose(Environment(procedural="sky", intensity=2.5).radiance(), 2.5 * sky().astype(np.float64))


def test_an_hdr_outside_the_scene_folder_is_refused(tmp_path):
    """The scene's read jail (core/files/read_jail.py) holds for [environment] hdr as for models and textures."""
    from wgpurender.core.errors import UserError
    from wgpurender.core.files.hdr_io import encode_hdr
    from wgpurender.core.scene import parse_scene

    (tmp_path / "outside.hdr").write_bytes(encode_hdr(np.ones((2, 4, 3))))
    (tmp_path / "project").mkdir()
    text = '[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\n[environment]\nhdr = "../outside.hdr"\n'
    with pytest.raises(UserError, match="outside.hdr"):
        parse_scene(text, tmp_path / "project" / "s.toml")
    (tmp_path / "project" / "inside.hdr").write_bytes(encode_hdr(np.ones((2, 4, 3))))
    scene = parse_scene(text.replace("../outside", "inside"), tmp_path / "project" / "s.toml")
    assert scene.environment.hdr.name == "inside.hdr"


@pytest.mark.parametrize("path", ["shaders_wgsl/ibl_shading.wgsl", "shaders_glsl/ibl_shading.glsl"])
def test_the_shaders_read_the_layout_ibl_maps_writes(path):
    """The sizes in the shaders' constants are core/course/ibl_maps.py's (the pack() layout's one home)."""
    import re

    from wgpurender.core.course import ibl_maps

    text = (ROOT / path).read_text()
    found = {name: int(value) for name, value in re.findall(r"IBL_(\w+)(?::\s*u32)?\s*=\s*(\d+)u;", text)}
    (iw, ih), (pw, ph) = ibl_maps.IRRADIANCE_SIZE, ibl_maps.PREFILTER_SIZE
    assert found == {"IRRADIANCE_W": iw, "IRRADIANCE_H": ih, "PREFILTER_W": pw, "PREFILTER_H": ph,
                     "LEVELS": ibl_maps.LEVELS, "LUT": ibl_maps.LUT_SIZE}
