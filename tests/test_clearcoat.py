"""KHR_materials_clearcoat against the float64 layering of tests/pbr_reference.py, on both paths.

The scenes are test_pbr.py's: a large glTF quad under one directional light, seen from (0, 0, 2) with a 90-degree
view, so each pixel's n, v and l follow from the camera and the plane; the whole image is compared with the
reference (base layer: the metallic-roughness BRDF plus the ambient term; coat: the extension's GGX layer plus the
ambient radiance; mixed by clearcoat x Fresnel on the coat's normal), sRGB-encoded as the output is. Hard cases:
clearcoat 0 and 1, coat roughness 0 (the documented clamp) and 1, grazing view and grazing light. Then the coat's
three textures (R weight, G roughness on TEXCOORD_1 with a KHR_texture_transform, a tangent-space normal with its
scale), image-based lighting under a uniform sky, and what --explain and the plan say.
"""

from __future__ import annotations

import numpy as np
import pbr_reference as ref
import pytest
from gltf_gen import QUAD_INDICES, GltfWriter, quad
from helpers import render_both_paths
from shading_model import course_constant, srgb_encode

from wgpurender.core.plan.gl_facts import CANNOT_DRAW

SIZE = (64, 64)
EYE = (0.0, 0.0, 2.0)
BASE = (0.9, 0.6, 0.3)
INTENSITY = 0.25
HALF = 40.0
TOWARDS_VIEW = (0.3, 0.2, 1.0)
COAT = "KHR_materials_clearcoat"
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
"""
LIGHT = """
[[lights]]
type = "directional"
direction = {direction}
intensity = {intensity}
"""

# name: (clearcoat, coat roughness, metallic, roughness, to-light l, turn of the plane about y (degrees), intensity,
#        emissive)
CASES = {
    "coat0": (0.0, 0.3, 0.0, 0.5, TOWARDS_VIEW, 0.0, INTENSITY, (0, 0, 0)),
    "coat1_rough0": (1.0, 0.0, 0.0, 0.6, TOWARDS_VIEW, 0.0, INTENSITY, (0, 0, 0)),
    "coat1_rough1": (1.0, 1.0, 0.0, 0.6, (0.2, 0.3, 1.0), 70.0, 2.0, (0, 0, 0)),
    "coat1_rough0.3_metal": (1.0, 0.3, 1.0, 0.7, TOWARDS_VIEW, 0.0, INTENSITY, (0, 0, 0)),
    "coat0.5_over_emission": (0.5, 0.2, 0.0, 0.5, (0.2, 0.3, 1.0), 70.0, 1.0, (0.6, 0.2, 0.0)),
    "grazing_view": (1.0, 0.2, 0.0, 0.8, (0.2, 0.3, 1.0), 80.0, 2.0, (0, 0, 0)),
    "grazing_view_rough1": (1.0, 1.0, 1.0, 0.5, (0.2, 0.3, 1.0), 80.0, 2.0, (0, 0, 0)),
    "grazing_light": (1.0, 0.1, 0.0, 0.4, (np.sqrt(1 - 0.02**2), 0.0, 0.02), 0.0, 8.0, (0, 0, 0)),
    "grazing_light_turned": (1.0, 0.3, 0.0, 0.4, (0.0, np.sqrt(1 - 0.02**2), 0.02), 70.0, 8.0, (0, 0, 0)),
}


def plane_view(turn_degrees: float = 0.0):
    """The plane's normal, each pixel's unit view vector and the mask of pixels whose centre sees the quad one
    pixel in from its outline (a pixel on the outline may go either way)."""
    turn = np.radians(turn_degrees)
    normal = np.array([np.sin(turn), 0.0, np.cos(turn)])
    rays = ref.pixel_rays(SIZE, 90.0)
    hits = ref.plane_hits(EYE, rays, normal)
    sees = (np.sum(rays * normal, axis=-1) < -1e-6) & (np.linalg.norm(hits - EYE, axis=-1) < 90.0)
    inner = sees.copy()
    inner[1:-1, 1:-1] = sees[1:-1, 1:-1] & sees[:-2, 1:-1] & sees[2:, 1:-1] & sees[1:-1, :-2] & sees[1:-1, 2:]
    inner[[0, -1], :] = inner[:, [0, -1]] = False
    return normal, ref.unit(np.asarray(EYE) - hits), inner


def write_plane(folder, coat: dict, metallic: float, roughness: float, turn_degrees: float = 0.0,
                emissive=(0, 0, 0), g: GltfWriter | None = None, extra_attributes: dict | None = None) -> None:
    g = g or GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [*BASE, 1.0], "metallicFactor": metallic,
                                           "roughnessFactor": roughness},
                     emissiveFactor=list(emissive), extensions={COAT: coat})
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    prim = {"attributes": {"POSITION": g.positions(quad(-HALF, -HALF, HALF, HALF)), "NORMAL": g.accessor(normals),
                           **(extra_attributes or {})}, "indices": g.accessor(QUAD_INDICES), "material": mat}
    half = np.radians(turn_degrees) / 2
    g.node(mesh=g.mesh([prim]), rotation=[0.0, float(np.sin(half)), 0.0, float(np.cos(half))])
    g.doc["extensionsUsed"] = [COAT]
    g.write(folder / "plane.glb")


def render_both(ctx, folder):
    return render_both_paths(ctx, folder, SIZE)


def assert_matches(image, linear, inner, bound: float = 2.0, what: str = "") -> None:
    """8-bit sRGB ``image`` within ``bound`` of the reference's ``linear`` radiance on the ``inner`` pixels."""
    assert np.all(np.isfinite(linear)), what
    assert inner.sum() > SIZE[0] * SIZE[1] // 4, what  # the comparison covers a real part of the image
    want = np.round(srgb_encode(linear) * 255)
    err = np.where(inner[..., None], np.abs(image - want), 0)
    worst = np.unravel_index(np.argmax(err), err.shape)
    assert err.max() <= bound, (what, err.max(), worst, image[worst[:2]].tolist(), want[worst[:2]].tolist())


def layered(clearcoat, coat_roughness, metallic, roughness, to_light, turn, intensity, emissive, nc=None):
    """The reference radiance (H, W, 3) and mask of a CASES row (nc: the coat's normal per pixel, else the plane's)."""
    n, v, inner = plane_view(turn)
    ambient = np.asarray(course_constant("AMBIENT"))
    base = ref.radiance(n, to_light, v, BASE, metallic, roughness, intensity) + ambient * np.asarray(BASE)
    base = base + np.asarray(emissive, np.float64)
    nc = n if nc is None else nc
    coat = ref.coat_radiance(nc, to_light, v, coat_roughness, intensity) + ambient
    return ref.coated(base, coat, nc, v, clearcoat), inner


@pytest.mark.parametrize("case", list(CASES))
def test_pixels_match_the_float64_layering_on_both_paths(ctx, tmp_path, case):
    clearcoat, coat_roughness, metallic, roughness, to_light, turn, intensity, emissive = CASES[case]
    write_plane(tmp_path, {"clearcoatFactor": clearcoat, "clearcoatRoughnessFactor": coat_roughness}, metallic,
                roughness, turn, emissive)
    direction = [-float(c) for c in ref.unit(to_light)]
    (tmp_path / "scene.toml").write_text(SCENE + LIGHT.format(direction=direction, intensity=intensity))
    image = render_both(ctx, tmp_path)
    assert_matches(image, *layered(*CASES[case]), what=case)


POINT = (0.4, 0.3, 0.8)  # a point light close above the plane: l and the irradiance change across the image


def test_a_point_light_lights_the_coat(ctx, tmp_path):
    """A point light of intensity 0.5 at POINT (irradiance 0.5 / d^2, scene.wgsl's header) over a coat of roughness
    0.15 on a rough metal: each pixel's l and E from its own hit point, against the float64 layering."""
    write_plane(tmp_path, {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.15}, 1.0, 0.8)
    (tmp_path / "scene.toml").write_text(SCENE + f'\n[[lights]]\ntype = "point"\nposition = {list(POINT)}\n'
                                         'intensity = 0.5\n')
    image = render_both(ctx, tmp_path)
    n, v, inner = plane_view()
    hits = ref.plane_hits(EYE, ref.pixel_rays(SIZE, 90.0), n)
    to_light = np.asarray(POINT) - hits
    irradiance = (0.5 / np.sum(to_light * to_light, -1))[..., None]
    ambient = np.asarray(course_constant("AMBIENT"))
    base = ref.radiance(n, to_light, v, BASE, 1.0, 0.8, irradiance) + ambient * np.asarray(BASE)
    coat = ref.coat_radiance(n, to_light, v, 0.15, irradiance) + ambient
    assert_matches(image, ref.coated(base, coat, n, v, 1.0), inner, what="point light")


# grazing_light is there for the numbers (n.l = 0.02 on both layers: nothing may blow up), too faint to tell a coat
@pytest.mark.parametrize("case", [c for c in CASES if CASES[c][0] > 0 and c != "grazing_light"])
def test_each_coated_case_differs_from_the_bare_material(case):
    """The pixel test can tell: with the coat dropped (clearcoat 0, all else equal) the reference image moves by
    more than the tolerance on a tenth of the pixels at least (the grazing view darkens the light the base reflects,
    a smooth coat adds a sharp highlight); at clearcoat 0 the layering is the bare material exactly."""
    coated, inner = layered(*CASES[case])
    bare, _ = layered(0.0, *CASES[case][1:])
    moved = np.abs(np.round(srgb_encode(coated) * 255) - np.round(srgb_encode(bare) * 255)).max(-1) > 2
    assert moved[inner].mean() > 0.1, (case, moved[inner].mean())
    n, v, _ = plane_view(CASES[case][5])
    plain = ref.radiance(n, CASES[case][4], v, BASE, *CASES[case][2:4], CASES[case][6])
    assert np.allclose(bare, plain + np.asarray(course_constant("AMBIENT")) * BASE + CASES[case][7], atol=0)


# -- the coat's textures, each on its own coordinates --------------------------------------------------------------

WEIGHT_TEXELS = np.array([[[255, 0, 0, 255], [90, 0, 0, 255]]], np.uint8)  # R: the coat's weight, left | right
ROUGH_TEXELS = np.array([[[0, 40, 0, 255], [0, 230, 0, 255]]], np.uint8)  # G: the coat's roughness
NORMAL_TEXEL = (210, 90, 200)  # a tangent-space normal tilted towards +x and -y (scaled by 0.6 below)
NORMAL_SCALE = 0.6


def test_textures_weight_roughness_and_normal_from_the_file(ctx, tmp_path):
    """clearcoatTexture (R) on TEXCOORD_0, clearcoatRoughnessTexture (G) on TEXCOORD_1 moved half a texture by
    KHR_texture_transform (so its halves swap), clearcoatNormalTexture (one texel, scale 0.6) with the file's
    TANGENT (+x, w 1: bitangent = cross(n, t) w = +y, glTF's rule). Factors 1: each pixel against the float64
    layering with the texel values and the coat normal the file gives."""
    g = GltfWriter()
    nearest = g.sampler(magFilter=9728, minFilter=9728)
    weight, rough = g.texture(WEIGHT_TEXELS, nearest), g.texture(ROUGH_TEXELS, nearest)
    normal_tex = g.texture(np.array([[[*NORMAL_TEXEL, 255]]], np.uint8), nearest)
    uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
    attributes = {"TEXCOORD_0": g.accessor(uvs), "TEXCOORD_1": g.accessor(uvs),
                  "TANGENT": g.accessor(np.tile(np.float32([1, 0, 0, 1]), (4, 1)))}
    shift = {"extensions": {"KHR_texture_transform": {"offset": [0.5, 0.0]}}}
    coat = {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 1.0, "clearcoatTexture": {"index": weight},
            "clearcoatRoughnessTexture": {"index": rough, "texCoord": 1, **shift},
            "clearcoatNormalTexture": {"index": normal_tex, "scale": NORMAL_SCALE}}
    write_plane(tmp_path, coat, 0.0, 0.6, g=g, extra_attributes=attributes)
    direction = [-float(c) for c in ref.unit(TOWARDS_VIEW)]
    (tmp_path / "scene.toml").write_text(SCENE + LIGHT.format(direction=direction, intensity=INTENSITY))
    image = render_both(ctx, tmp_path)
    right = np.broadcast_to(np.arange(SIZE[0]) + 0.5 > SIZE[0] / 2, SIZE[::-1])
    clearcoat = np.where(right, WEIGHT_TEXELS[0, 1, 0], WEIGHT_TEXELS[0, 0, 0]) / 255.0
    coat_rough = np.where(right, ROUGH_TEXELS[0, 0, 1], ROUGH_TEXELS[0, 1, 1]) / 255.0  # u + 0.5: halves swapped
    m = np.asarray(NORMAL_TEXEL) / 255.0 * 2 - 1
    nc = ref.unit([m[0] * NORMAL_SCALE, m[1] * NORMAL_SCALE, m[2]])  # t = +x, b = +y, n = +z
    linear, inner = layered(clearcoat, coat_rough, 0.0, 0.6, TOWARDS_VIEW, 0.0, INTENSITY, (0, 0, 0),
                            nc=np.broadcast_to(nc, (*SIZE[::-1], 3)))
    away_from_seam = np.abs(np.arange(SIZE[0]) + 0.5 - SIZE[0] / 2) > 2
    assert_matches(image, linear, inner & away_from_seam[None, :], what="textured coat")


# -- image-based lighting --------------------------------------------------------------------------------------------

SKY = 0.6  # a uniform environment: every prefiltered texel is SKY, so the split sums alone shape the image


@pytest.mark.parametrize(("coat_roughness", "occlusion"), [(0.0, None), (0.5, None), (1.0, None), (0.5, 128)])
def test_environment_lights_the_coat_with_its_split_sum(ctx, tmp_path, coat_roughness, occlusion):
    """No lights, a uniform sky of radiance SKY: a black dielectric reflects SKY x S(0.04) of its roughness, the coat
    SKY x S(1) of its own (S: tests/pbr_reference.split_sum, the hemisphere integral of F D V n.l, by its own
    quadrature), mixed by clearcoat x Fc; an occlusion texel R (strength 1) scales both by R / 255. Tolerance: the
    renderer's 32x32 table of 256 Hammersley samples against the integral, 2% of the coat's term, plus 2/255."""
    from wgpurender.core.files.hdr_io import encode_hdr

    (tmp_path / "sky.hdr").write_bytes(encode_hdr(np.full((8, 16, 3), SKY)))
    g = GltfWriter()
    occluded = {} if occlusion is None else {
        "occlusionTexture": {"index": g.texture(np.array([[[occlusion, 0, 0, 255]]], np.uint8))}}
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [0, 0, 0, 1.0], "metallicFactor": 0.0,
                                           "roughnessFactor": 1.0}, **occluded,
                     extensions={COAT: {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": coat_roughness}})
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-HALF, -HALF, HALF, HALF)),
                                        "NORMAL": g.accessor(normals), "TEXCOORD_0": g.accessor(uvs)},
                         "indices": g.accessor(QUAD_INDICES), "material": mat}]))
    g.write(tmp_path / "plane.glb")
    (tmp_path / "scene.toml").write_text(SCENE + '\n[environment]\nhdr = "sky.hdr"\n')
    image = render_both(ctx, tmp_path)
    n, v, inner = plane_view()
    pick = np.flatnonzero(inner.reshape(-1))[::29]
    n_dot_v = np.clip(v.reshape(-1, 3)[pick] @ n, 0, 1)
    base = np.array([SKY * ref.split_sum(c, 1.0, 0.04) for c in n_dot_v])
    coat = np.array([SKY * ref.split_sum(c, coat_roughness, 1.0) for c in n_dot_v])
    w = ref.clearcoat_fresnel(n, v.reshape(-1, 3)[pick])
    want = (base * (1 - w) + coat * w) * (1.0 if occlusion is None else occlusion / 255)
    got = image.reshape(-1, 3)[pick]
    low, high = (np.round(srgb_encode(want * k) * 255) for k in (0.98, 1.02))
    assert np.all((got >= low[:, None] - 2) & (got <= high[:, None] + 2)), (got[:, 0], low, high)


# -- what the plan and --explain say ---------------------------------------------------------------------------------

def test_only_the_coated_material_pays_and_explain_says_so(tmp_path, capsys):
    """Three materials: coated (with a texture), coat 0 (the extension's 'disabled'), no coat. Only the first
    gets the clearcoat variant, its texture and sampler; --explain gives the reason and the note."""
    from wgpurender.cli import main

    g = GltfWriter()
    tex = g.texture(WEIGHT_TEXELS)
    prims = []
    for k, coat in enumerate(({"clearcoatFactor": 0.7, "clearcoatTexture": {"index": tex}},
                              {"clearcoatFactor": 0.0, "clearcoatTexture": {"index": tex}}, None)):
        mat = g.material(name=f"m{k}", extensions={COAT: coat} if coat else {})
        uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
        prims.append({"attributes": {"POSITION": g.positions(quad(k - 1.5, -0.5, k - 0.5, 0.5)),
                                     "NORMAL": g.accessor(np.tile(np.float32([0, 0, 1]), (4, 1))),
                                     "TEXCOORD_0": g.accessor(uvs)},
                      "indices": g.accessor(QUAD_INDICES), "material": mat})
    g.node(mesh=g.mesh(prims))
    g.write(tmp_path / "plane.glb")
    (tmp_path / "scene.toml").write_text(SCENE + LIGHT.format(direction=[0, 0, -1], intensity=1.0))
    assert main(["render", str(tmp_path / "scene.toml"), "--explain", "-o", str(tmp_path / "out.png")]) == 0
    out = capsys.readouterr().out
    assert "'m0': KHR_materials_clearcoat, clearcoatFactor 0.7, clearcoatRoughnessFactor 0:" in out  # its default
    assert "clearcoatTexture (R channel x clearcoatFactor)" in out
    assert "'m1': KHR_materials_clearcoat with clearcoatFactor 0: no coat" in out
    pipelines = [line for line in out.splitlines() if "| rgba8unorm-srgb x1 |" in line and "<-" not in line]
    assert len(pipelines) == 2 and sum("clearcoat" in p for p in pipelines) == 1, pipelines
    assert "KHR_materials_clearcoat: ignored" not in out  # neither the materials' extension nor extensionsUsed


def test_a_file_that_requires_clearcoat_is_accepted_and_unlit_ignores_it(tmp_path, capsys):
    """extensionsRequired KHR_materials_clearcoat draws; on a KHR_materials_unlit material (the extension's
    exclusion) the coat is ignored by name."""
    from wgpurender.cli import main

    write_plane(tmp_path, {"clearcoatFactor": 1.0}, 0.0, 0.5)
    import json
    import struct

    data = (tmp_path / "plane.glb").read_bytes()
    length = struct.unpack("<I", data[12:16])[0]
    doc = json.loads(data[20:20 + length])
    doc["extensionsRequired"] = [COAT]
    doc["materials"][0]["extensions"]["KHR_materials_unlit"] = {}
    from gltf_gen import write_container

    bin_start = 20 + length
    write_container(tmp_path / "plane.glb", {k: v for k, v in doc.items() if k != "buffers"},
                    data[bin_start + 8:])
    (tmp_path / "scene.toml").write_text(SCENE + LIGHT.format(direction=[0, 0, -1], intensity=1.0))
    assert main(["render", str(tmp_path / "scene.toml"), "--explain", "-o", str(tmp_path / "out.png")]) == 0
    out = capsys.readouterr().out
    assert "KHR_materials_clearcoat: ignored (KHR_materials_unlit draws the base colour only)" in out


@pytest.mark.parametrize(("coat", "says"), [
    ({"clearcoatFactor": "1"}, "clearcoatFactor"),
    ({"clearcoatFactor": -0.5}, "clearcoatFactor"),
    ({"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": [0.1]}, "clearcoatRoughnessFactor"),
    ({"clearcoatFactor": 1.0, "clearcoatTexture": {"index": 7}}, "clearcoatTexture"),
    ({"clearcoatFactor": 1.0, "clearcoatNormalTexture": {"index": 0, "scale": "x"}}, "scale"),
    ({"clearcoatFactor": 1.0, "clearcoatRoughnessTexture": {"texCoord": 0}}, "clearcoatRoughnessTexture"),
])
def test_a_malformed_coat_is_one_line_and_exit_2(tmp_path, capsys, coat, says):
    """Wrong types, a negative factor, a texture that does not exist, a textureInfo without its index: one line
    naming the member, exit 2, no traceback."""
    from wgpurender.cli import main

    g = GltfWriter()
    g.texture(WEIGHT_TEXELS)  # texture 0 exists
    write_plane(tmp_path, coat, 0.0, 0.5, g=g)
    (tmp_path / "scene.toml").write_text(SCENE + LIGHT.format(direction=[0, 0, -1], intensity=1.0))
    assert main(["render", str(tmp_path / "scene.toml"), "-o", str(tmp_path / "out.png")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err and says in err, err
    assert not (tmp_path / "out.png").exists()


def test_a_sixth_coordinate_choice_is_ignored_by_name(tmp_path):
    """Eight textures on six distinct (set, transform) choices: the mesh carries five slots (the vertex stage's 16
    attributes), the last texture is listed as ignored and not sampled."""
    from wgpurender.core.scene.gltf_materials import file_material

    g = GltfWriter()
    tex = g.texture(WEIGHT_TEXELS)

    def info(k: int) -> dict:
        return {"index": tex, "extensions": {"KHR_texture_transform": {"offset": [0.1 * k, 0.0]}}}

    coat = {"clearcoatFactor": 1.0, "clearcoatTexture": info(5), "clearcoatRoughnessTexture": info(0),
            "clearcoatNormalTexture": info(1)}
    g.material(name="many", normalTexture=info(0), occlusionTexture=info(4), emissiveTexture=info(3),
               pbrMetallicRoughness={"baseColorTexture": info(1), "metallicRoughnessTexture": info(2)},
               extensions={COAT: coat})
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-1, -1, 1, 1)), "NORMAL": g.accessor(normals),
                                        "TEXCOORD_0": g.accessor(np.zeros((4, 2), np.float32))},
                         "indices": g.accessor(QUAD_INDICES), "material": 0}]))
    g.write(tmp_path / "many.glb")
    from wgpurender.core.scene.gltf_materials import document

    ignored: list[str] = []
    material = file_material(document(str(tmp_path / "many.glb")), 0, "many.glb", False, ignored)
    assert material.clearcoat_map is None and material.clearcoat_roughness_map is not None
    assert any("clearcoatTexture ignored: it samples a sixth distinct texture coordinate choice" in line
               for line in ignored), ignored
    assert max(k for _, k, _ in material.uv_slots) == 4
    assert material.clearcoat_normal_scale == 1.0  # normalTextureInfo's default scale


# -- the most a material can bind --------------------------------------------------------------------------------------

def write_every_map(folder) -> None:
    """A quad whose one material has every map (eight textures on five coordinate slots), COLOR_0, a mask, a
    uniform sky and a light: the largest material group there is."""
    from wgpurender.core.files.hdr_io import encode_hdr

    (folder / "sky.hdr").write_bytes(encode_hdr(np.full((8, 16, 3), SKY)))
    g = GltfWriter()
    tex = g.texture(np.array([[[200, 120, 220, 255], [90, 200, 128, 255]]], np.uint8))

    def info(k: int, texcoord: int = 0) -> dict:
        return {"index": tex, "texCoord": texcoord,
                "extensions": {"KHR_texture_transform": {"offset": [0.25 * k, 0.0]}}}

    coat = {"clearcoatFactor": 0.8, "clearcoatRoughnessFactor": 0.4, "clearcoatTexture": info(3),
            "clearcoatRoughnessTexture": info(4, 1), "clearcoatNormalTexture": info(0)}
    mat = g.material(normalTexture=info(0), occlusionTexture=info(1), emissiveTexture=info(2),
                     emissiveFactor=[0.1, 0.1, 0.0], alphaMode="MASK", doubleSided=True,
                     pbrMetallicRoughness={"baseColorTexture": info(1), "metallicRoughnessTexture": info(2)},
                     extensions={COAT: coat})
    uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    colours = np.tile(np.float32([1, 0.9, 0.8, 1]), (4, 1))
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-HALF, -HALF, HALF, HALF)),
                                        "NORMAL": g.accessor(normals), "TEXCOORD_0": g.accessor(uvs),
                                        "TEXCOORD_1": g.accessor(uvs[::-1].copy()), "COLOR_0": g.accessor(colours)},
                         "indices": g.accessor(QUAD_INDICES), "material": mat}]))
    g.doc["extensionsUsed"] = [COAT, "KHR_texture_transform"]
    g.write(folder / "plane.glb")
    direction = [-float(c) for c in ref.unit(TOWARDS_VIEW)]
    (folder / "scene.toml").write_text(SCENE + '\n[environment]\nhdr = "sky.hdr"\n'
                                       + LIGHT.format(direction=direction, intensity=INTENSITY))


@pytest.mark.parametrize("instance_data", ["storage", "vertex"])
def test_every_map_at_once_fits_both_paths_limits(ctx, tmp_path, instance_data):
    """The largest material group: all eight textures with their eight samplers (WebGPU's default limits are 16 of
    each a stage) and the environment's storage buffer, on five coordinate slots (uv, uv1-uv4: with the seven
    per-instance attributes of instance_data "vertex" that is all 16 vertex attributes); the coat's factors in the
    push constants (lavapipe: 128 bytes). Both paths draw it without a validation error (tests/conftest.py) and
    alike, and the plan counts the bindings."""
    from wgpurender.core.plan.model import TEXTURE_FEATURES
    from wgpurender.core.plan.resolve import resolve_plan
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.raw_path.scene.scene_subpass import material_block_size
    from wgpurender.wgpu_path.scene import render_scene_file

    write_every_map(tmp_path)
    knobs = {"post_path": "fragment", "instance_data": instance_data}
    plan = resolve_plan(tmp_path / "scene.toml", None, size=SIZE, **knobs)
    (variant,) = plan.variants
    assert set(TEXTURE_FEATURES) <= variant.flags and {"ibl", "clearcoat", "vertex_color"} <= variant.flags
    assert len(variant.vertex_attributes) == 9  # position, normal, uv, tangent, color, uv1-uv4
    assert material_block_size(variant) <= 128
    wgpu = render_scene_file(tmp_path / "scene.toml", size=SIZE, ctx=ctx, frames=1, knobs=knobs).pixels
    raw = render_scene_reference(tmp_path / "scene.toml", size=SIZE)
    assert np.array_equal(wgpu, raw)
    assert wgpu[..., :3].std() > 5  # the textures show


def test_the_browser_draws_the_coat_as_wgpu_native_does(ctx, tmp_path):
    """Dawn's WGSL compiler (Tint) is stricter than naga (facts.md): two clearcoat variants exported as pages (no
    immediates there: the material in a uniform buffer), drawn by headless Chromium on SwiftShader, compile without
    an error. A plain coat (the coat1_rough1 case) draws within 2/255 of wgpu-native (measured 1/255 here); the
    every-map material differs by more than 2/255 on at most 2% of its pixels (measured 0.95%, up to 9/255, all in
    the bottom six rows; why there was not investigated)."""
    from wgpurender.webpage import export
    from wgpurender.webpage.chromium import Chromium, find_chromium
    from wgpurender.wgpu_path.scene import render_scene_file

    if find_chromium() is None:
        pytest.skip("chromium is not installed (apt-get install chromium)")
    plain, every = tmp_path / "plain", tmp_path / "every"
    plain.mkdir()
    every.mkdir()
    clearcoat, coat_roughness, metallic, roughness, to_light, turn, intensity, _ = CASES["coat1_rough1"]
    write_plane(plain, {"clearcoatFactor": clearcoat, "clearcoatRoughnessFactor": coat_roughness}, metallic,
                roughness, turn)
    direction = [-float(c) for c in ref.unit(to_light)]
    (plain / "scene.toml").write_text(SCENE + LIGHT.format(direction=direction, intensity=intensity))
    write_every_map(every)
    off = {}
    with Chromium(webgpu=True) as session:
        for folder in (plain, every):
            tab = session.open(export(str(folder / "scene.toml"), folder / "page", SIZE).page)
            image = tab.capture()
            assert tab.errors() == [], folder.name
            native = render_scene_file(folder / "scene.toml", size=SIZE, ctx=ctx, frames=1).pixels
            off[folder.name] = np.abs(native.astype(int) - image.astype(int))[..., :3].max(-1)
    assert off["plain"].max() <= 2, off["plain"].max()
    assert (off["every"] > 2).mean() <= 0.02, (off["every"] > 2).mean()


GL_CHILD = """
import sys, numpy as np
from wgpurender import api
np.save(sys.argv[2], api.render(sys.argv[1], backend="opengl", size=(64, 64)).pixels)
"""


def test_the_gl_backend_draws_coated_materials_as_vulkan_does(ctx, tmp_path):
    """wgpu's OpenGL backend has no usable immediates (facts.md), so each material's block goes into one uniform
    buffer at the adapter's offset alignment. A coated material's block (48 bytes; 64 with every map) is larger than
    the course's 32-byte one, which the buffer's slices were sized for: on llvmpipe's GL, whose alignment is small,
    the upload ran past the buffer ('Invalid data_length', a traceback). Both scenes now draw there, within 2/255
    of the Vulkan path (llvmpipe against lavapipe; measured 0 and 1)."""
    import os
    import subprocess
    import sys

    from wgpurender.wgpu_path.scene import render_scene_file

    plain, every = tmp_path / "plain", tmp_path / "every"
    plain.mkdir()
    every.mkdir()
    write_plane(plain, {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.2}, 0.0, 0.6)
    (plain / "scene.toml").write_text(SCENE + LIGHT.format(direction=[-0.3, -0.2, -1.0], intensity=1.0))
    write_every_map(every)
    for folder in (plain, every):
        done = subprocess.run([sys.executable, "-c", GL_CHILD, str(folder / "scene.toml"), str(folder / "gl.npy")],
                              capture_output=True, text=True, timeout=300, env=dict(os.environ))
        if "no OpenGL adapter" in done.stderr or CANNOT_DRAW in done.stderr:  # none, or one refused (NVIDIA's)
            pytest.skip("this machine has no usable OpenGL adapter: " + done.stderr.strip()[-200:])
        assert done.returncode == 0, done.stderr[-1500:]
        gl = np.load(folder / "gl.npy")
        vulkan = render_scene_file(folder / "scene.toml", size=SIZE, ctx=ctx, frames=1).pixels
        assert np.abs(gl.astype(int) - vulkan.astype(int)).max() <= 2, folder.name
