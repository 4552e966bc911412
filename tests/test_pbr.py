"""glTF metallic-roughness materials against the float64 BRDF of tests/pbr_reference.py, on both paths.

Each scene is a large glTF quad (its own material, a node rotation turning its normal) under one directional
light, seen from (0, 0, 2) with a 90-degree view: every pixel's n, v and l follow from the camera and the plane
alone (pbr_reference.plane_hits), so the whole image is compared with the BRDF, sRGB-encoded as the output
format does, plus the ambient term (ambient x base colour, scene.wgsl's header). The hard cases: grazing light
(n.l = 0.02), grazing view (the plane turned 80 degrees: n.v down to ~0.05), roughness 0 (the documented clamp)
and 1, metal 0, 1 and between. wgpu and raw agree exactly within one run.
"""

from __future__ import annotations

import numpy as np
import pbr_reference as ref
import pytest
from gltf_gen import QUAD_INDICES, GltfWriter, quad
from shading_model import course_constant, srgb_encode

SIZE = (64, 64)
EYE = (0.0, 0.0, 2.0)
BASE = (0.9, 0.6, 0.3)
INTENSITY = 0.25
SCENE = f"""[camera]
eye = [{EYE[0]}, {EYE[1]}, {EYE[2]}]
target = [0, 0, 0]
fov_y = 90
near = 0.1
far = 100

[render]
size = [{SIZE[0]}, {SIZE[1]}]
msaa = 1
hdr = false
clear_color = [0, 0, 0, 1]

[[models]]
path = "plane.glb"

[[lights]]
type = "directional"
direction = {{direction}}
intensity = {{intensity}}
"""
HALF = 40.0  # the quad's half size: wider than the view at every angle used here
TOWARDS_VIEW = (0.3, 0.2, 1.0)  # the light comes from here (l before normalising): its mirror highlight is in view

# name: (metallic, roughness, to-light l, turn of the plane about y in degrees[, light intensity])
CASES = {
    "dielectric_rough0.5": (0.0, 0.5, TOWARDS_VIEW, 0.0),
    "metal_rough0.5": (1.0, 0.5, TOWARDS_VIEW, 0.0),
    "dielectric_rough1": (0.0, 1.0, TOWARDS_VIEW, 0.0),
    "metal_rough1": (1.0, 1.0, TOWARDS_VIEW, 0.0),
    "dielectric_rough0": (0.0, 0.0, TOWARDS_VIEW, 0.0),
    "metal_rough0": (1.0, 0.0, TOWARDS_VIEW, 0.0),
    "half_metal_rough0.3": (0.5, 0.3, TOWARDS_VIEW, 0.0),
    "grazing_light": (0.0, 0.4, (np.sqrt(1 - 0.02**2), 0.0, 0.02), 0.0, 8.0),
    "grazing_light_metal": (1.0, 0.2, (0.0, np.sqrt(1 - 0.02**2), 0.02), 0.0, 8.0),
    "grazing_view": (0.0, 0.3, (0.2, 0.3, 1.0), 80.0, 2.0),
    "grazing_view_metal": (1.0, 0.6, (0.2, 0.3, 1.0), 80.0, 4.0),
}


def write_plane(folder, metallic: float, roughness: float, turn_degrees: float) -> None:
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [*BASE, 1.0], "metallicFactor": metallic,
                                           "roughnessFactor": roughness})
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    prim = {"attributes": {"POSITION": g.positions(quad(-HALF, -HALF, HALF, HALF)), "NORMAL": g.accessor(normals)},
            "indices": g.accessor(QUAD_INDICES), "material": mat}
    half = np.radians(turn_degrees) / 2
    g.node(mesh=g.mesh([prim]), rotation=[0.0, float(np.sin(half)), 0.0, float(np.cos(half))])
    g.write(folder / "plane.glb")


def expected(metallic: float, roughness: float, to_light, turn_degrees: float, intensity: float = INTENSITY, **kw):
    """(H, W, 3) sRGB bytes the BRDF predicts and the mask of pixels whose centre sees the quad, one pixel in
    from its outline (a pixel on the outline may go either way)."""
    turn = np.radians(turn_degrees)
    normal = np.array([np.sin(turn), 0.0, np.cos(turn)])
    rays = ref.pixel_rays(SIZE, 90.0)
    hits = ref.plane_hits(EYE, rays, normal)
    distance = np.linalg.norm(hits - EYE, axis=-1)
    sees = (np.sum(rays * normal, axis=-1) < -1e-6) & (distance < 90.0)
    v = ref.unit(np.asarray(EYE) - hits)
    light = ref.radiance(normal, to_light, v, BASE, metallic, roughness, intensity, **kw)
    linear = light + np.asarray(course_constant("AMBIENT")) * np.asarray(BASE)
    inner = sees.copy()
    inner[1:-1, 1:-1] = sees[1:-1, 1:-1] & sees[:-2, 1:-1] & sees[2:, 1:-1] & sees[1:-1, :-2] & sees[1:-1, 2:]
    inner[[0, -1], :] = inner[:, [0, -1]] = False
    return np.round(srgb_encode(linear) * 255), inner, linear


def render_both(ctx, folder):
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.wgpu_path.scene import render_scene_file

    path = folder / "scene.toml"
    wgpu = render_scene_file(path, size=SIZE, ctx=ctx, frames=1, knobs={"post_path": "fragment"}).pixels
    return wgpu, render_scene_reference(path, size=SIZE)


@pytest.mark.parametrize("case", list(CASES))
def test_pixels_match_the_float64_brdf_on_both_paths(ctx, tmp_path, case):
    metallic, roughness, to_light, turn, *intensity = CASES[case]
    write_plane(tmp_path, metallic, roughness, turn)
    direction = [-float(c) for c in ref.unit(to_light)]
    (tmp_path / "scene.toml").write_text(SCENE.format(direction=direction, intensity=(intensity or [INTENSITY])[0]))
    wgpu, raw = render_both(ctx, tmp_path)
    assert np.array_equal(wgpu, raw), f"{case}: wgpu and raw differ"
    want, inner, linear = expected(*CASES[case])
    assert inner.sum() > SIZE[0] * SIZE[1] // 4, case  # the comparison covers a real part of the image
    err = np.abs(wgpu[..., :3].astype(np.float64) - want)[inner]
    worst = np.unravel_index(np.argmax(np.where(inner[..., None], np.abs(wgpu[..., :3] - want), 0)), want.shape)
    assert err.max() <= 2, (case, err.max(), worst, wgpu[worst[:2]].tolist(), want[worst[:2]].tolist())
    assert np.all(np.isfinite(linear))


def test_roughness_zero_needs_the_clamp():
    """At roughness 0 the naive formulas (alpha = 0) give D = 0 / 0 = NaN in the mirror direction and 0 elsewhere:
    a metal is black except for NaN; the documented clamp (roughness >= 0.045, pbr.wgsl) makes the peak finite and
    large. Evaluated in float64 from the spec's formulas (the same naive arithmetic is NaN in float32 too)."""
    n, to_light = np.array([0.0, 0.0, 1.0]), ref.unit([0.3, 0.2, 1.0])
    mirror = to_light * [-1, -1, 1]  # v = l reflected about n: h = n
    off = ref.unit([0.1, 0.0, 1.0])
    naive = {name: ref.brdf(n, to_light, v, BASE, 1.0, 0.0, min_roughness=None) for name, v in
             (("mirror", mirror), ("off", off))}
    assert np.isnan(naive["mirror"]).all()
    assert np.array_equal(naive["off"], np.zeros(3))  # black away from the mirror direction
    clamped = ref.brdf(n, to_light, mirror, BASE, 1.0, 0.0)
    assert np.isfinite(clamped).all() and (clamped > 1e3).all()
    for grazing in (ref.unit([1.0, 0.0, 1e-9]), ref.unit([0.0, 1.0, 0.0])):  # n.v -> 0 and = 0: finite
        assert np.isfinite(ref.brdf(n, to_light, grazing, BASE, 0.5, 0.0)).all()


# -- the MetalRoughSpheres equivalent --------------------------------------------------------------------------------

SPHERES_BASE = (1.0, 0.71, 0.29)  # assets/make_assets.py: SPHERE_BASE (the file's baseColorFactor)
GRID = 5  # metallic 0..1 bottom to top, roughness 0..1 left to right, spacing 1, radius 0.42, in z = 0


@pytest.fixture(scope="module")
def spheres():
    """The repository scene on both paths at its own size: linear pixels and the raw 8-bit image."""
    from pathlib import Path

    from shading_model import srgb_decode

    from wgpurender.core.scene import load_scene
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene import render_scene_file

    path = Path(__file__).resolve().parents[1] / "assets" / "scenes" / "metal_rough_spheres.toml"
    scene = load_scene(path)
    raw = render_scene_reference(path)
    wgpu = render_scene_file(path, ctx=get_context(), frames=1, knobs={"post_path": "fragment"}).pixels
    return scene, raw[..., :3], wgpu[..., :3], srgb_decode(raw[..., :3] / 255.0)


def sphere_disc(scene, row: int, col: int, shrink: float = 0.8) -> np.ndarray:
    """Pixels within ``shrink`` of the projected radius of sphere (row, col) (row 0: metallic 0, at the bottom)."""
    w, h = scene.render.size
    distance = np.linalg.norm(np.subtract(scene.camera.eye, scene.camera.target))
    half_h = distance * np.tan(np.radians(scene.camera.fov_y) / 2)
    x, y = col - (GRID - 1) / 2, row - (GRID - 1) / 2
    cx, cy = (x / (half_h * w / h) + 1) / 2 * w, (1 - y / half_h) / 2 * h
    radius = 0.42 / half_h * h / 2 * shrink
    ys, xs = np.mgrid[0:h, 0:w] + 0.5
    return (xs - cx) ** 2 + (ys - cy) ** 2 <= radius * radius


def test_spheres_render_alike_on_both_paths(spheres):
    _, raw, wgpu, _ = spheres
    assert np.array_equal(raw, wgpu)


def test_roughness_zero_dielectric_has_a_small_bright_highlight(spheres):
    """Bottom-left sphere: its brightest pixel stands well above the diffuse body (median), and only a few pixels
    reach half-way up."""
    scene, _, _, lin = spheres
    lum = lin[sphere_disc(scene, 0, 0)].sum(-1)
    body = np.median(lum)
    assert lum.max() - body > 0.5
    assert 1 <= (lum >= body + 0.5 * (lum.max() - body)).sum() <= 4


def test_metal_spheres_take_the_base_colour(spheres):
    """Top row (metallicFactor 1): the light a metal adds to the ambient term has the base colour's channel
    ratios (Schlick F with f0 = the base colour; v.h >= 0.85 on these spheres, so F's whitening (1 - v.h)^5 is
    below 1e-4; a dielectric-looking metal, f0 = 0.04, would reflect white). The known ambient term (AMBIENT x base
    colour, scene.wgsl; AMBIENT is bluish, so a mostly-ambient pixel's blue/red is 0.34 rather than 0.29) is taken
    off first. Bound, per sphere: the median pixel's ratio interval when each channel is off by one byte (the
    rounding to 8 bits plus an implementation's sRGB-encode rounding), propagated through the decode and the
    ratio."""
    from shading_model import srgb_decode

    scene, raw, _, lin = spheres
    ambient = np.asarray(course_constant("AMBIENT")) * np.asarray(SPHERES_BASE)
    for col in range(GRID):
        disc = sphere_disc(scene, GRID - 1, col)
        pixels = raw[disc].astype(np.float64)
        direct = lin[disc] - ambient
        low, high = (srgb_decode(np.clip(pixels + d, 0, 255) / 255.0) - ambient for d in (-1, 1))
        lit = (pixels < 250).all(-1) & (direct[:, 0] > 0.05)  # lit well above the ambient term, below saturation
        assert lit.sum() >= 1, col  # every sphere has a highlight
        for channel in (1, 2):
            want = SPHERES_BASE[channel] / SPHERES_BASE[0]
            ratio = direct[lit, channel] / direct[lit, 0]
            spread = (high[lit, channel] / low[lit, 0] - low[lit, channel] / high[lit, 0]) / 2
            assert abs(np.median(ratio) - want) <= np.median(spread), (col, channel, np.median(ratio), want)


@pytest.mark.parametrize("row", [GRID - 2, GRID - 1])
def test_highlight_width_grows_with_roughness(spheres, row):
    """The two most metallic rows (no diffuse to hide the lobe): the number of pixels at or above half the
    sphere's peak grows strictly from roughness 0 to 1."""
    scene, _, _, lin = spheres
    widths = []
    for col in range(GRID):
        lum = lin[sphere_disc(scene, row, col)].sum(-1)
        widths.append(int((lum >= 0.5 * lum.max()).sum()))
    assert all(a < b for a, b in zip(widths, widths[1:], strict=False)), widths


# -- the metallic-roughness texture, the defaults, --explain --------------------------------------------------------

MR_TEXELS = np.array([[[0, 77, 0, 255], [0, 153, 255, 255]]], np.uint8)  # G roughness, B metal (linear data)


def test_metallic_roughness_texture_blue_is_metal_green_is_rough(ctx, tmp_path):
    """A 2x1 metallicRoughnessTexture (nearest) across the quad: the left half is a dielectric of roughness
    77/255, the right half a metal of roughness 153/255 (factors 1): each pixel against the float64 BRDF."""
    g = GltfWriter()
    tex = g.texture(MR_TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33071))
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [*BASE, 1.0], "metallicRoughnessTexture": {"index": tex}})
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
    prim = {"attributes": {"POSITION": g.positions(quad(-HALF, -HALF, HALF, HALF)), "NORMAL": g.accessor(normals),
                           "TEXCOORD_0": g.accessor(uvs)}, "indices": g.accessor(QUAD_INDICES), "material": mat}
    g.node(mesh=g.mesh([prim]))
    g.write(tmp_path / "plane.glb")
    (tmp_path / "scene.toml").write_text(SCENE.format(direction=[-float(c) for c in ref.unit(TOWARDS_VIEW)],
                                                      intensity=INTENSITY))
    wgpu, raw = render_both(ctx, tmp_path)
    assert np.array_equal(wgpu, raw)
    right = np.broadcast_to(np.arange(SIZE[0]) + 0.5 > SIZE[0] / 2, SIZE[::-1])
    metallic = np.where(right, MR_TEXELS[0, 1, 2], MR_TEXELS[0, 0, 2])[..., None] / 255.0
    roughness = np.where(right, MR_TEXELS[0, 1, 1], MR_TEXELS[0, 0, 1]) / 255.0
    rays = ref.pixel_rays(SIZE, 90.0)
    hits = ref.plane_hits(EYE, rays, np.array([0.0, 0.0, 1.0]))
    light = ref.radiance([0, 0, 1], TOWARDS_VIEW, ref.unit(np.asarray(EYE) - hits), BASE, metallic, roughness,
                         INTENSITY)
    want = np.round(srgb_encode(light + np.asarray(course_constant("AMBIENT")) * np.asarray(BASE)) * 255)
    away_from_seam = np.abs(np.arange(SIZE[0]) + 0.5 - SIZE[0] / 2) > 2
    err = np.abs(wgpu[..., :3].astype(np.float64) - want)[:, away_from_seam]
    assert err.max() <= 2, err.max()


def test_default_material_values_and_explain(tmp_path, capsys):
    """A glTF material with no pbrMetallicRoughness takes the spec's defaults (metallic 1, roughness 1, white), and
    --explain says which model each draw uses: the file's material the metallic-roughness one, the scene's own
    material (a second model) Blinn-Phong, with one pbr pipeline variant only."""
    from wgpurender.cli import main

    g = GltfWriter()
    mat = g.material(name="plain")
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-1, -1, 1, 1)), "NORMAL": g.accessor(normals)},
                         "indices": g.accessor(QUAD_INDICES), "material": mat}]))
    g.write(tmp_path / "plane.glb")
    text = SCENE.format(direction=[0, 0, -1], intensity=1.0)
    text += '\n[[models]]\npath = "plane.glb"\nmaterial = { albedo_color = [1, 0, 0, 1] }\n'
    (tmp_path / "scene.toml").write_text(text)
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 0
    out = capsys.readouterr().out
    assert "base_color=(1, 1, 1, 1), roughness=1, normal_strength=1, metallic=1\n" in out
    assert "is a glTF metallic-roughness material: metallicFactor 1" in out
    assert "models[1].material (inline) shades with the course's Blinn-Phong" in out
    variants = [line for line in out.splitlines() if "| rgba8unorm-srgb x1 |" in line and "<-" not in line]
    assert len(variants) == 2 and sum("+pbr" in v for v in variants) == 1, variants


def test_an_included_glsl_file_is_part_of_the_spirv_cache_key(tmp_path, monkeypatch):
    """scene.frag includes pbr.glsl: editing the included file alone must give new SPIR-V, not the cached one."""
    from wgpurender.raw_path.device.shaders import compile_glsl

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    (tmp_path / "a.frag").write_text('#version 450\n#extension GL_GOOGLE_include_directive : require\n'
                                     '#include "b.glsl"\nlayout(location = 0) out vec4 c;\n'
                                     'void main() { c = vec4(K); }\n')
    (tmp_path / "b.glsl").write_text("const float K = 0.25;\n")
    first = compile_glsl(tmp_path / "a.frag")
    (tmp_path / "b.glsl").write_text("const float K = 0.75;\n")
    assert compile_glsl(tmp_path / "a.frag") != first
