"""KHR_materials_pbrSpecularGlossiness, converted to metallic-roughness at load (core/scene/gltf_specgloss.py).

Every file is built here (tests/gltf_gen.py). The expected conversion is the extension appendix's formula
written out again below in float64 (:func:`expected`), never the loader's; the renders compare a spec-gloss file
with the metallic-roughness file the formula says it equals, on each path.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from gltf_gen import GltfWriter, quad, scene_text
from test_gltf_render import PATHS, SIZE, at, quad_primitive, render, srgb_decode, srgb_encode

EXT = "KHR_materials_pbrSpecularGlossiness"
LIGHT = '\n[[lights]]\ntype = "directional"\ndirection = [0.4, -0.5, -1]\n'
UVS = [[0, 1], [1, 1], [1, 0], [0, 0]]
NEAREST = {"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33071}


def expected(diffuse, specular, glossiness):
    """The appendix's conversion for one material, in plain float64 arithmetic: (base RGBA, metallic, roughness)."""
    a = 0.04

    def bright(c):
        return math.sqrt(0.299 * c[0] ** 2 + 0.587 * c[1] ** 2 + 0.114 * c[2] ** 2)

    one_minus = 1 - max(specular)
    d, p = bright(diffuse), bright(specular)
    if p < a:
        metallic = 0.0
    else:
        b = d * one_minus / (1 - a) + p - 2 * a
        c = a - p
        metallic = min(max((-b + math.sqrt(b * b - 4 * a * c)) / (2 * a), 0.0), 1.0)
    base = []
    for k in range(3):
        from_diffuse = diffuse[k] * one_minus / (1 - a) / max(1 - metallic, 1e-6)
        from_specular = (specular[k] - a * (1 - metallic)) / max(metallic, 1e-6)
        base.append(min(max(from_diffuse + (from_specular - from_diffuse) * metallic ** 2, 0.0), 1.0))
    return (*base, diffuse[3]), metallic, 1 - glossiness


def _materials(path):
    from wgpurender.core.scene.gltf_materials import model_materials

    return model_materials(path, "m")


def _one_quad(g: GltfWriter, material: int, path):
    g.node(mesh=g.mesh([quad_primitive(g, -1.6, -1.6, 1.6, 1.6, material, uvs=UVS)]))
    return g.write(path)


def test_factors_follow_the_formula(tmp_path):
    """A coloured spec-gloss material (no exact metal-rough equivalent): base colour, metallic and roughness are
    the float64 formula's; --explain's line for it says converted, an approximation."""
    diffuse, specular, gloss = (0.5, 0.4, 0.3, 0.8), (0.3, 0.25, 0.2), 0.6
    g = GltfWriter()
    mat = g.material(extensions={EXT: {"diffuseFactor": list(diffuse), "specularFactor": list(specular),
                                       "glossinessFactor": gloss}})
    found = _materials(_one_quad(g, mat, tmp_path / "sg.glb"))
    m = found.materials[0]
    base, metallic, roughness = expected(diffuse, specular, gloss)
    assert 0.05 < metallic < 0.95  # a real mix: every term of the formula counts
    assert np.allclose(m.albedo_color, base, atol=1e-9), (m.albedo_color, base)
    assert m.metallic == pytest.approx(metallic, abs=1e-9) and m.roughness == pytest.approx(roughness, abs=1e-9)
    assert m.roughness_map_scale == pytest.approx(roughness, abs=1e-9) and m.shading_model == "pbr"
    assert found.taken[0].startswith(m.origin + ": ")
    assert found.taken[0].endswith(f", converted from {EXT} to metallic-roughness (an approximation)"), found.taken


def test_defaults_are_the_extensions(tmp_path):
    """An empty extension object: diffuse 1, specular 1, glossiness 1 -> a white metal, roughness 0."""
    g = GltfWriter()
    m = _materials(_one_quad(g, g.material(extensions={EXT: {}}), tmp_path / "sg.glb")).materials[0]
    base, metallic, roughness = expected((1, 1, 1, 1), (1, 1, 1), 1.0)
    assert np.allclose(m.albedo_color, base) and m.metallic == pytest.approx(metallic) and m.roughness == roughness


# (spec-gloss factors, the metallic-roughness factors the appendix says they equal exactly)
EXACT = [({"diffuseFactor": [0.6, 0.3, 0.2, 1], "specularFactor": [0.04] * 3, "glossinessFactor": 0.5},
          {"baseColorFactor": [0.6, 0.3, 0.2, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5}),
         ({"diffuseFactor": [0, 0, 0, 1], "specularFactor": [0.9, 0.6, 0.3], "glossinessFactor": 0.7},
          {"baseColorFactor": [0.9, 0.6, 0.3, 1], "metallicFactor": 1.0, "roughnessFactor": 0.3})]


def _two_quads(tmp_path, name, materials):
    g = GltfWriter()
    mats = [g.material(**fields) for fields in materials]
    g.node(mesh=g.mesh([quad_primitive(g, -1.8, -1.2, -0.1, 1.2, mats[0], uvs=UVS),
                        quad_primitive(g, 0.1, -1.2, 1.8, 1.2, mats[1], uvs=UVS)]))
    g.write(tmp_path / name)
    path = tmp_path / f"{name}.toml"
    path.write_text(scene_text(name, SIZE, None, LIGHT))
    return path


@pytest.mark.parametrize("which", PATHS)
def test_exact_cases_render_as_their_metal_rough_equivalent(ctx, tmp_path, which):
    """A dielectric (specular 0.04 grey) and a metal (black diffuse): each lit quad renders the same pixels as
    the metallic-roughness file with the appendix's equivalent factors (max 1/255: the factors in float32)."""
    sg = render(ctx, _two_quads(tmp_path, "sg.glb", [{"extensions": {EXT: s}} for s, _ in EXACT]), which)
    mr = render(ctx, _two_quads(tmp_path, "mr.glb", [{"pbrMetallicRoughness": p} for _, p in EXACT]), which)
    for x in (-0.95, 0.95):
        assert at(mr, x, 0.0).max() > 20  # lit: the comparison is not black against black
    assert np.abs(sg.astype(int) - mr.astype(int)).max() <= 1, which
    for spec_gloss, pbr in EXACT:
        base, metallic, roughness = expected(spec_gloss["diffuseFactor"], spec_gloss["specularFactor"],
                                             spec_gloss["glossinessFactor"])
        assert np.allclose(base, pbr["baseColorFactor"]) and metallic == pytest.approx(pbr["metallicFactor"])
        assert roughness == pytest.approx(pbr["roughnessFactor"])


DIFFUSE_TEXELS = np.array([[[200, 40, 10, 255], [0, 0, 0, 255]]], np.uint8)  # sRGB: a dielectric | a metal
SPECGLOSS_TEXELS = np.array([[[56, 56, 56, 128], [230, 160, 90, 200]]], np.uint8)  # sRGB spec (56 ~ 0.04), gloss


def _expected_texels(factor_diffuse, factor_specular, factor_gloss):
    """The converted base-colour (sRGB bytes) and metallic-roughness (G roughness, B metallic) texels."""
    base_texels, mr_texels = np.zeros((1, 2, 4)), np.zeros((1, 2, 4))
    for col in range(2):
        d, s = DIFFUSE_TEXELS[0, col], SPECGLOSS_TEXELS[0, col]
        diffuse = (*(srgb_decode(d[:3]) * factor_diffuse[:3]), d[3] / 255 * factor_diffuse[3])
        specular = tuple(srgb_decode(s[:3]) * factor_specular)
        base, metallic, roughness = expected(diffuse, specular, s[3] / 255 * factor_gloss)
        base_texels[0, col] = (*srgb_encode(base[:3]), base[3] * 255)
        mr_texels[0, col] = (0, roughness * 255, metallic * 255, 255)
    return base_texels, mr_texels


def _textured_specgloss(tmp_path, factors):
    g = GltfWriter()
    sampler = g.sampler(**NEAREST)
    ext = {"diffuseTexture": {"index": g.texture(DIFFUSE_TEXELS, sampler)},
           "specularGlossinessTexture": {"index": g.texture(SPECGLOSS_TEXELS, sampler)}, **factors}
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = [EXT]
    return _one_quad(g, g.material(extensions={EXT: ext}), tmp_path / "sgtex.glb")


FACTORS = {"diffuseFactor": [0.9, 1.0, 0.8, 0.9], "specularFactor": [1.0, 0.9, 1.0], "glossinessFactor": 0.9}


def test_textures_are_converted_per_texel(tmp_path):
    """Two 2x1 textures (diffuse, specular-glossiness) with factors: each texel of the converted base-colour and
    metallic-roughness images is the formula's (within 1/255: 8-bit rounding), and the factors are folded in."""
    from wgpurender.core.scene.texture_pixels import load_image

    found = _materials(_textured_specgloss(tmp_path, FACTORS))
    m = found.materials[0]
    base_want, mr_want = _expected_texels(FACTORS["diffuseFactor"], FACTORS["specularFactor"],
                                          FACTORS["glossinessFactor"])
    base, mr = load_image(m.albedo_map).astype(float), load_image(m.roughness_map).astype(float)
    assert np.abs(base - base_want).max() <= 1.0, (base.tolist(), base_want.round(1).tolist())
    assert np.abs(mr[..., 1:3] - mr_want[..., 1:3]).max() <= 1.0, (mr.tolist(), mr_want.round(1).tolist())
    assert mr[0, 0, 2] < 2 and mr[0, 1, 2] > 200  # texel 0 a dielectric, texel 1 a metal
    assert m.albedo_color == (1.0, 1.0, 1.0, 1.0) and m.metallic == 1.0 and m.roughness_map_scale == 1.0
    assert f"converted from {EXT} to metallic-roughness per texel (an approximation" in found.taken[0]


@pytest.mark.parametrize("which", PATHS)
def test_textured_renders_as_the_converted_metal_rough_file(ctx, tmp_path, which):
    """The textured spec-gloss quad renders as a metallic-roughness quad whose textures are the test's own
    formula's texels (each half one texel: left a dielectric, right a metal), within 2/255."""
    sg_scene = tmp_path / "sg.toml"
    sg_scene.write_text(scene_text(_textured_specgloss(tmp_path, {}).name, SIZE, None, LIGHT))
    base_want, mr_want = _expected_texels((1, 1, 1, 1), (1, 1, 1), 1.0)
    g = GltfWriter()
    sampler = g.sampler(**NEAREST)
    pbr = {"baseColorTexture": {"index": g.texture(np.round(base_want).astype(np.uint8), sampler)},
           "metallicRoughnessTexture": {"index": g.texture(np.round(mr_want).astype(np.uint8), sampler)}}
    _one_quad(g, g.material(pbrMetallicRoughness=pbr), tmp_path / "mr.glb")
    mr_scene = tmp_path / "mr.toml"
    mr_scene.write_text(scene_text("mr.glb", SIZE, None, LIGHT))
    sg, mr = render(ctx, sg_scene, which), render(ctx, mr_scene, which)
    assert np.abs(at(mr, -0.8, 0) - at(mr, 0.8, 0)).max() > 20  # the two texels differ on screen
    assert np.abs(sg.astype(int) - mr.astype(int)).max() <= 2, which


def test_required_spec_gloss_is_rendered_and_explained(tmp_path, capsys):
    """extensionsRequired lists the extension: rendered (exit 0, no refusal), and --explain says the material was
    converted from spec-gloss, exactly for a dielectric; the extension is listed as used, not ignored."""
    from wgpurender.cli import main

    g = GltfWriter()
    mat = g.material(name="bottle", extensions={EXT: EXACT[0][0]})
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-1, -1, 1, 1))}, "material": mat,
                         "indices": g.accessor(np.array([0, 1, 2, 0, 2, 3], np.uint16))}]))
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = [EXT]
    g.write(tmp_path / "req.glb")
    scene = tmp_path / "req.toml"
    scene.write_text(scene_text("req.glb", SIZE, None, LIGHT))
    code = main(["render", str(scene), "-o", str(tmp_path / "out.png"), "--explain"])
    captured = capsys.readouterr()
    assert code == 0 and (tmp_path / "out.png").exists(), captured.err
    line = next(t for t in captured.out.splitlines() if "'bottle':" in t)
    assert line.endswith(f", converted from {EXT} to metallic-roughness (exact)"), line
    assert f"extensionsUsed {EXT}: used" in captured.out and f"{EXT}: ignored" not in captured.out


def _refused(tmp_path, capsys, model: str, needle: str) -> None:
    """Rendering ``model`` is the one-line refusal (exit 2) naming the extension and ``needle``; no image."""
    from helpers import one_line_refusal

    from wgpurender.cli import main

    scene = tmp_path / "refused.toml"
    scene.write_text(scene_text(model, SIZE))
    code = main(["render", str(scene), "-o", str(tmp_path / "out.png")])
    err = "\n".join(line for line in capsys.readouterr().err.splitlines() if line.strip())
    one_line_refusal(code, err, EXT, needle)
    assert not (tmp_path / "out.png").exists()


def test_textures_sampling_differently_are_refused_in_one_line(tmp_path, capsys):
    """diffuseTexture on TEXCOORD_0, specularGlossinessTexture on TEXCOORD_1: not convertible per texel, so one
    line naming the extension, exit 2."""

    g = GltfWriter()
    tex = g.texture(DIFFUSE_TEXELS)
    ext = {"diffuseTexture": {"index": tex}, "specularGlossinessTexture": {"index": tex, "texCoord": 1}}
    prim = quad_primitive(g, -1, -1, 1, 1, g.material(extensions={EXT: ext}), uvs=UVS)
    prim["attributes"]["TEXCOORD_1"] = prim["attributes"]["TEXCOORD_0"]
    g.node(mesh=g.mesh([prim]))
    g.write(tmp_path / "two.glb")
    _refused(tmp_path, capsys, "two.glb", "different coordinates")


def test_textures_of_different_sizes_are_refused_in_one_line(tmp_path, capsys):
    """A 2x1 diffuseTexture and a 1x1 specularGlossinessTexture: no texel-to-texel conversion, so one line naming
    the extension and the fix, exit 2."""

    g = GltfWriter()
    ext = {"diffuseTexture": {"index": g.texture(DIFFUSE_TEXELS)},
           "specularGlossinessTexture": {"index": g.texture(SPECGLOSS_TEXELS[:, :1])}}
    _one_quad(g, g.material(extensions={EXT: ext}), tmp_path / "sizes.glb")
    _refused(tmp_path, capsys, "sizes.glb", "differ in size")


@pytest.mark.parametrize("which", PATHS)
def test_a_diffuse_texture_on_texcoord_1_keeps_its_coordinates(ctx, tmp_path, which):
    """diffuseTexture alone, texCoord 1 (TEXCOORD_0 all zeros: sampling it would show texel 0 everywhere): both
    converted images sample TEXCOORD_1, so the quad renders as the metallic-roughness file whose textures (the
    test's formula, specular 0.04 grey and glossiness 0.5 as factors) sample TEXCOORD_1 too, within 2/255."""
    factors = {"specularFactor": [0.04] * 3, "glossinessFactor": 0.5}
    base_want, mr_want = np.zeros((1, 2, 4)), np.zeros((1, 2, 4))
    for col in range(2):
        d = DIFFUSE_TEXELS[0, col]
        base, metallic, roughness = expected((*srgb_decode(d[:3]), d[3] / 255), (0.04,) * 3, 0.5)
        base_want[0, col] = (*srgb_encode(base[:3]), base[3] * 255)
        mr_want[0, col] = (0, roughness * 255, metallic * 255, 255)
    scenes = []
    for name, textures in (("sg1.glb", None), ("mr1.glb", (base_want, mr_want))):
        g = GltfWriter()
        sampler = g.sampler(**NEAREST)
        if textures is None:
            ext = {"diffuseTexture": {"index": g.texture(DIFFUSE_TEXELS, sampler), "texCoord": 1}, **factors}
            mat = g.material(extensions={EXT: ext})
        else:
            infos = [{"index": g.texture(np.round(t).astype(np.uint8), sampler), "texCoord": 1} for t in textures]
            mat = g.material(pbrMetallicRoughness={"baseColorTexture": infos[0], "metallicRoughnessTexture": infos[1]})
        prim = quad_primitive(g, -1.6, -1.6, 1.6, 1.6, mat, uvs=UVS)
        prim["attributes"]["TEXCOORD_1"] = prim["attributes"]["TEXCOORD_0"]
        prim["attributes"]["TEXCOORD_0"] = g.accessor(np.zeros((4, 2), np.float32))
        g.node(mesh=g.mesh([prim]))
        g.write(tmp_path / name)
        scenes.append(tmp_path / f"{name}.toml")
        scenes[-1].write_text(scene_text(name, SIZE, None, LIGHT))
    sg, mr = render(ctx, scenes[0], which), render(ctx, scenes[1], which)
    assert np.abs(at(mr, -0.8, 0) - at(mr, 0.8, 0)).max() > 20  # the two texels differ on screen
    assert np.abs(sg.astype(int) - mr.astype(int)).max() <= 2, which


def test_bands_cover_every_row(tmp_path, monkeypatch):
    """Random 5x3 textures converted in bands of 2 rows (the last band short): every texel is the formula's
    (within 1/255), so no band is skipped, shifted or cut."""
    from wgpurender.core.scene import gltf_specgloss
    from wgpurender.core.scene.texture_pixels import load_image

    monkeypatch.setattr(gltf_specgloss, "BAND_ROWS", 2)
    rng = np.random.default_rng(30)
    diffuse_texels, sg_texels = (rng.integers(0, 256, (5, 3, 4), dtype=np.uint8) for _ in range(2))
    g = GltfWriter()
    ext = {"diffuseTexture": {"index": g.texture(diffuse_texels)},
           "specularGlossinessTexture": {"index": g.texture(sg_texels)}}
    m = _materials(_one_quad(g, g.material(extensions={EXT: ext}), tmp_path / "bands.glb")).materials[0]
    base, mr = load_image(m.albedo_map).astype(float), load_image(m.roughness_map).astype(float)
    for row in range(5):
        for col in range(3):
            d, s = diffuse_texels[row, col], sg_texels[row, col]
            want, metallic, roughness = expected((*srgb_decode(d[:3]), d[3] / 255), tuple(srgb_decode(s[:3])),
                                                 s[3] / 255)
            assert np.abs(base[row, col] - (*srgb_encode(want[:3]), want[3] * 255)).max() <= 1.0, (row, col)
            assert np.abs(mr[row, col, 1:3] - (roughness * 255, metallic * 255)).max() <= 1.0, (row, col)
