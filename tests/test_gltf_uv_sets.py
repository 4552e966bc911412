"""One material, textures on different coordinate sets and transforms (glTF texCoord per texture,
KHR_texture_transform per texture, as MultiUVTest and TextureTransformMultiTest use them), on both paths.

Each quad is written here (tests/gltf_gen.py) with TEXCOORD_0 and a TEXCOORD_1 turned by 90 degrees; every
expected colour is computed from the file's numbers: the spec's transform of each texture's own set, the texel
it selects (nearest filtering, repeat wrap), and the scene's shading (no lights: ambient x base colour x
occlusion + emissive; the ambient is the scene model's documented constant).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from gltf_gen import QUAD_INDICES, GltfWriter, quad
from test_gltf_render import PATHS, SIZE, assert_colour, render, srgb_decode, srgb_encode, write_scene

from wgpurender.core.course.shading import AMBIENT

HALF = 1.6  # the quad spans -HALF..HALF in x and y
UV0 = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)  # u0 = (x + H) / 2H, v0 = (H - y) / 2H
UV1 = np.array([[1, 1], [1, 0], [0, 0], [0, 1]], np.float32)  # u1 = (H - y) / 2H, v1 = (H - x) / 2H
# 2x2 textures, channels kept apart so each term of the sum can be read alone: the base colour in R only, the
# emissive in G and B only, the occlusion (linear, R read) a grey level per texel.
BASE = np.array([[[255, 0, 0, 255], [0, 0, 0, 255]], [[0, 0, 0, 255], [255, 0, 0, 255]]], np.uint8)
EMISSIVE = np.array([[[0, 255, 0, 255], [0, 0, 255, 255]], [[0, 0, 0, 255], [0, 255, 255, 255]]], np.uint8)
OCCLUSION = np.array([[[255, 255, 255, 255], [64, 64, 64, 255]], [[160, 160, 160, 255], [0, 0, 0, 255]]], np.uint8)
FLAT = np.full((2, 2, 4), (128, 128, 255, 255), np.uint8)  # a flat normal map: it only orders the slots here

# case -> {texture role: (texCoord, KHR_texture_transform or None)}
CASES = {
    "base0_offset+emissive1_scale": {"base": (0, {"offset": [0.5, 0.0]}), "emissive": (1, {"scale": [2.0, 1.0]})},
    "occlusion1_rotation+emissive0": {"occlusion": (1, {"rotation": 0.4, "offset": [0.1, 0.2]}),
                                      "emissive": (0, None)},
    "base0_two_transforms_one_set": {"base": (0, None), "emissive": (0, {"offset": [0.5, 0.5]})},
    # four slots: the normal texture's choice is slot 0 (its tangents), so the base colour samples slot 1
    "four_slots": {"normal": (0, None), "base": (1, None), "emissive": (0, {"offset": [0.5, 0.0]}),
                   "occlusion": (1, {"rotation": 0.4, "offset": [0.1, 0.2]})},
}
IMAGES = {"base": BASE, "emissive": EMISSIVE, "occlusion": OCCLUSION, "normal": FLAT}


def _info(index: int, texcoord: int, transform: dict | None) -> dict:
    info = {"index": index, "texCoord": texcoord}
    if transform is not None:
        info["extensions"] = {"KHR_texture_transform": transform}
    return info


def write_case(tmp_path, case: str) -> str:
    g = GltfWriter()
    nearest = g.sampler(magFilter=9728, minFilter=9728, wrapS=10497, wrapT=10497)
    infos = {role: _info(g.texture(IMAGES[role], nearest), *CASES[case][role]) for role in CASES[case]}
    fields: dict = {"pbrMetallicRoughness": {"metallicFactor": 0.0}}
    if "base" in infos:
        fields["pbrMetallicRoughness"]["baseColorTexture"] = infos["base"]
    if "emissive" in infos:
        fields.update(emissiveTexture=infos["emissive"], emissiveFactor=[1.0, 1.0, 1.0])
    if "occlusion" in infos:
        fields["occlusionTexture"] = infos["occlusion"]
    if "normal" in infos:
        fields["normalTexture"] = infos["normal"]
    mat = g.material(**fields)
    attributes = {"POSITION": g.positions(quad(-HALF, -HALF, HALF, HALF)), "TEXCOORD_0": g.accessor(UV0),
                  "TEXCOORD_1": g.accessor(UV1)}
    g.node(mesh=g.mesh([{"attributes": attributes, "indices": g.accessor(QUAD_INDICES), "material": mat}]))
    g.doc["extensionsUsed"] = ["KHR_texture_transform"]
    g.write(tmp_path / f"{case}.glb")
    return f"{case}.glb"


def texel_at(x: float, y: float, texcoord: int, transform: dict | None) -> tuple[int, int] | None:
    """(row, col) of the 2x2 texel a texture samples at quad point (x, y): its own set's (u, v) under the spec's
    T(offset) R(rotation) S(scale), rotation matrix [[cos, sin], [-sin, cos]]; None within 0.06 of a texel edge."""
    a, b = (x + HALF) / (2 * HALF), (HALF - y) / (2 * HALF)
    u, v = (a, b) if texcoord == 0 else (b, 1.0 - a)
    t = transform or {}
    (ox, oy), (sx, sy), r = t.get("offset", (0, 0)), t.get("scale", (1, 1)), t.get("rotation", 0.0)
    tu = ox + math.cos(r) * sx * u + math.sin(r) * sy * v
    tv = oy - math.sin(r) * sx * u + math.cos(r) * sy * v
    fu, fv = (tu % 1.0) * 2, (tv % 1.0) * 2
    if min(abs(fu - round(fu)), abs(fv - round(fv))) < 0.12:
        return None
    return int(fv) % 2, int(fu) % 2


def expected_colour(case: str, x: float, y: float) -> np.ndarray | None:
    """Linear RGB: ambient x base x occlusion + emissive, each texture at its own texel (None: near an edge)."""
    texels = {role: texel_at(x, y, *CASES[case][role]) for role in CASES[case] if role != "normal"}
    if any(t is None for t in texels.values()):
        return None
    base = srgb_decode(BASE[texels["base"]][:3]) if "base" in texels else np.ones(3)
    occlusion = OCCLUSION[texels["occlusion"]][0] / 255 if "occlusion" in texels else 1.0
    emissive = srgb_decode(EMISSIVE[texels["emissive"]][:3]) if "emissive" in texels else np.zeros(3)
    return np.asarray(AMBIENT) * base * occlusion + emissive


def checked_points(image, case: str, what: str) -> int:
    checked = 0
    for x in np.linspace(-1.4, 1.4, 9):
        for y in np.linspace(-1.4, 1.4, 9):
            want = expected_colour(case, x, y)
            if want is not None:
                assert_colour(image, x, y, want, f"{what} {case}", tol=4.0)
                checked += 1
    return checked


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("which", PATHS)
def test_each_texture_samples_its_own_set_and_transform(ctx, tmp_path, which, case):
    """Every point shows each texture's texel under its own texCoord and transform; drawing every texture with
    the first texture's coordinates (what the loader did before) fails at most points."""
    image = render(ctx, write_scene(tmp_path, write_case(tmp_path, case)), which)
    assert checked_points(image, case, which) >= 12


def test_the_expectation_tells_the_sets_apart():
    """The cases can fail: drawn with one slot for every texture, most points would show another colour."""
    for case, roles in CASES.items():
        first = next(iter(roles.values()))
        shared = {role: first for role in roles}
        differ = sum(1 for x in np.linspace(-1.4, 1.4, 9) for y in np.linspace(-1.4, 1.4, 9)
                     if _differs(case, shared, x, y))
        assert differ >= 12, case


def _differs(case: str, shared: dict, x: float, y: float) -> bool:
    want = expected_colour(case, x, y)
    saved = CASES[case]
    CASES[case] = shared
    try:
        other = expected_colour(case, x, y)
    finally:
        CASES[case] = saved
    return want is not None and other is not None and np.abs(want - other).max() > 0.02


def test_wgpu_equals_raw_within_one_run(ctx, tmp_path):
    """Both paths carry the second slot and pick the same set per texture: the same bytes on this machine."""
    scene = write_scene(tmp_path, write_case(tmp_path, "occlusion1_rotation+emissive0"))
    np.testing.assert_array_equal(render(ctx, scene, "wgpu"), render(ctx, scene, "raw"))


def test_plan_keeps_the_second_slot_for_the_materials_that_need_it(tmp_path):
    """Only a material whose textures sample two (set, transform) choices gets uv1 and a ``<map>_uv1`` flag; one
    set and one transform for every texture costs nothing (no second attribute, no flag)."""
    from wgpurender.core.plan.resolve import resolve_plan

    two = resolve_plan(write_scene(tmp_path, write_case(tmp_path, "base0_offset+emissive1_scale")), None)
    (variant,) = two.variants
    assert "emissive_map_uv1" in variant.flags and "albedo_map_uv1" not in variant.flags
    assert variant.vertex_attributes[-1] == "uv1"
    CASES["same"] = {"base": (1, {"scale": [2.0, 1.0]}), "emissive": (1, {"scale": [2.0, 1.0]})}
    try:
        one = resolve_plan(write_scene(tmp_path, write_case(tmp_path, "same")), None)
    finally:
        del CASES["same"]
    (variant,) = one.variants
    assert "uv1" not in variant.vertex_attributes and not any(f.endswith("_uv1") for f in variant.flags)


def test_explain_lists_each_slot_as_used(tmp_path, capsys):
    """Each texture's slot, set and transform, by name: the base colour on TEXCOORD_1 (slot 1), the emissive's
    offset (slot 2), the occlusion's rotation on TEXCOORD_1 (slot 3); the normal texture's choice is slot 0."""
    from wgpurender.cli import main

    assert main(["render", str(write_scene(tmp_path, write_case(tmp_path, "four_slots"))), "--explain"]) == 0
    out = capsys.readouterr().out
    for flag in ("albedo_map_uv1", "emissive_map_uv2", "occlusion_map_uv3"):
        assert flag in out, flag
    assert "TEXCOORD_1: coordinate slot 1" in out and "{'offset': (0.5, 0.0)}: coordinate slot 2" in out
    assert "vertex attributes: position, normal, uv, tangent, uv1, uv2, uv3" in out
    assert "normal_map_uv" not in out and "ignored" not in out.split("KHR_texture_transform")[-1]


def test_a_texcoord_the_primitive_lacks_is_one_line(tmp_path):
    """An emissive texture on texCoord 1 of a primitive without TEXCOORD_1 (the glTF validator's error): one line
    naming what is missing, exit 2, not a silent image sampled at (0, 0)."""
    from helpers import one_line_refusal
    from reliab_gen import run_cli

    g = GltfWriter()
    tex = g.texture(EMISSIVE)
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex}},
                     emissiveTexture={"index": tex, "texCoord": 1}, emissiveFactor=[1, 1, 1])
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-1, -1, 1, 1)), "TEXCOORD_0": g.accessor(UV0)},
                         "indices": g.accessor(QUAD_INDICES), "material": mat}]))
    g.write(tmp_path / "lacks.glb")
    code, _, err = run_cli("render", write_scene(tmp_path, "lacks.glb"), "-o", tmp_path / "x.png")
    one_line_refusal(code, err, "samples a set of texture coordinates", "TEXCOORD_n")
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("transform, field", [({"texCoord": "b"}, "texCoord"), ({"texCoord": -1}, "texCoord"),
                                              ({"offset": ["x", 0]}, "offset"), ({"scale": [1.0]}, "scale"),
                                              ({"rotation": "quarter"}, "rotation")])
def test_a_malformed_texture_transform_is_one_line(tmp_path, transform, field):
    """KHR_texture_transform's schema: texCoord a non-negative integer, offset and scale two numbers, rotation a
    number. Each broken field is named in one line, exit 2 (a ValueError traceback before; found by review)."""
    from helpers import one_line_refusal
    from reliab_gen import run_cli

    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": _info(g.texture(BASE), 0, transform)})
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-1, -1, 1, 1)), "TEXCOORD_0": g.accessor(UV0)},
                         "indices": g.accessor(QUAD_INDICES), "material": mat}]))
    g.doc["extensionsUsed"] = ["KHR_texture_transform"]
    g.write(tmp_path / "bad.glb")
    code, _, err = run_cli("render", write_scene(tmp_path, "bad.glb"), "-o", tmp_path / "x.png")
    one_line_refusal(code, err, f"KHR_texture_transform.{field}")
    assert not (tmp_path / "x.png").exists()


# A lit case, against the float64 metallic-roughness BRDF (tests/pbr_reference.py): the base colour on TEXCOORD_0,
# the metallic-roughness texture (G roughness, B metalness) on TEXCOORD_1 with a transform of its own.
LIT_BASE = np.array([[[230, 120, 60, 255], [90, 200, 120, 255]], [[120, 140, 230, 255], [200, 200, 200, 255]]],
                    np.uint8)
LIT_MR = np.array([[[0, 110, 0, 255], [0, 200, 255, 255]], [[0, 150, 255, 255], [0, 90, 0, 255]]], np.uint8)
LIT_MR_TRANSFORM = {"scale": [2.0, 1.0], "rotation": 0.3}
TO_LIGHT = (0.3, 0.2, 1.0)
LIT_INTENSITY = 0.6


@pytest.mark.parametrize("which", PATHS)
def test_metallic_roughness_texture_on_its_own_set_against_the_float64_brdf(ctx, tmp_path, which):
    """Each pixel inside the quad and away from a texel edge of either texture: the BRDF with the base colour's
    texel (its set 0) and the metallic-roughness texel its own set 1 and transform pick, within 3/255."""
    import pbr_reference as ref

    g = GltfWriter()
    nearest = g.sampler(magFilter=9728, minFilter=9728, wrapS=10497, wrapT=10497)
    mat = g.material(pbrMetallicRoughness={
        "baseColorTexture": {"index": g.texture(LIT_BASE, nearest)},
        "metallicRoughnessTexture": {"index": g.texture(LIT_MR, nearest), "texCoord": 1,
                                     "extensions": {"KHR_texture_transform": LIT_MR_TRANSFORM}}})
    attributes = {"POSITION": g.positions(quad(-HALF, -HALF, HALF, HALF)), "TEXCOORD_0": g.accessor(UV0),
                  "TEXCOORD_1": g.accessor(UV1), "NORMAL": g.accessor(np.tile(np.float32([0, 0, 1]), (4, 1)))}
    g.node(mesh=g.mesh([{"attributes": attributes, "indices": g.accessor(QUAD_INDICES), "material": mat}]))
    g.write(tmp_path / "mr.glb")
    light = (f'[[lights]]\ntype = "directional"\ndirection = {[-float(c) for c in ref.unit(TO_LIGHT)]}\n'
             f"intensity = {LIT_INTENSITY}\n")
    image = render(ctx, write_scene(tmp_path, "mr.glb", extra=light), which)[..., :3].astype(np.float64)
    eye = np.array([0.0, 0.0, 2.0])
    hits = ref.plane_hits(eye, ref.pixel_rays(SIZE, 90.0), np.array([0.0, 0.0, 1.0]))
    checked = 0
    for row, col in np.ndindex(*SIZE[::-1]):
        x, y = hits[row, col, :2]
        if max(abs(x), abs(y)) > HALF - 0.05:
            continue
        base_texel, mr_texel = texel_at(x, y, 0, None), texel_at(x, y, 1, LIT_MR_TRANSFORM)
        if base_texel is None or mr_texel is None:
            continue
        base = srgb_decode(LIT_BASE[base_texel][:3])
        metallic, roughness = LIT_MR[mr_texel][2] / 255, LIT_MR[mr_texel][1] / 255
        v = ref.unit(eye - hits[row, col])
        linear = ref.radiance([0, 0, 1], TO_LIGHT, v, base, metallic, roughness, LIT_INTENSITY)
        want = srgb_encode(linear + np.asarray(AMBIENT) * base)
        assert np.abs(image[row, col] - want).max() <= 3, (which, row, col, image[row, col], want.round(1))
        checked += 1
    assert checked > 2000
