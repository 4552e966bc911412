"""glTF files render as their authors meant, on both paths (wgpu and raw Vulkan), checked against the file.

Every model is generated here (tests/gltf_gen.py) and every expectation is computed from the numbers written into
it: where a vertex lands (gltf_gen.pixel_of: the camera at z = 2, fov 90), which colour a corner has. The two
paths share the loader, so agreeing with each other proves nothing about it: each is checked against the file.
"""

from __future__ import annotations

import numpy as np
import pytest
from gltf_gen import QUAD_INDICES, GltfWriter, pixel_of, quad, scene_text

from wgpurender.core.files.imageio import to_uint8

SIZE = (96, 96)
PATHS = ("wgpu", "raw")


def render(ctx, path, which: str, size=SIZE) -> np.ndarray:
    """The (H, W, 4) uint8 image of a scene file on one path (sRGB-encoded output)."""
    if which == "wgpu":
        from wgpurender.wgpu_path.scene import render_scene_file

        pixels = render_scene_file(path, size=size, ctx=ctx, frames=1, knobs={"post_path": "fragment"}).pixels
    else:
        from wgpurender.raw_path.scene import render_scene_reference

        pixels = render_scene_reference(path, size=size)
    return to_uint8(pixels) if pixels.dtype != np.uint8 else pixels


def write_scene(tmp_path, model: str, material: str | None = None, extra: str = "", size=SIZE):
    path = tmp_path / "scene.toml"
    path.write_text(scene_text(model, size, material, extra))
    return path


# -- sparse positions -------------------------------------------------------------------------------------------

SPARSE_X = np.float32([-1.5, -0.5, 0.5, 1.5])
SPARSE_TOP = np.float32([0.3, 0.8, 1.3])  # the sparse block's heights for top vertices 5, 6, 7


def _sparse_strip(tmp_path):
    """Bottom row y = -1.5, top row y = 0 in the base data; the sparse block lifts top vertices 5, 6, 7."""
    base = np.array([[x, -1.5, 0] for x in SPARSE_X] + [[x, 0, 0] for x in SPARSE_X], np.float32)
    changed = np.array([5, 6, 7], np.uint8)
    values = base[changed].copy()
    values[:, 1] = SPARSE_TOP
    g = GltfWriter()
    faces = np.array([[k, k + 1, k + 5, k, k + 5, k + 4] for k in range(3)], np.uint16).ravel()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(base, sparse=(changed, values))},
                         "indices": g.accessor(faces)}]))
    return g.write(tmp_path / "sparse.glb")


@pytest.mark.parametrize("which", PATHS)
def test_sparse_positions_render_displaced(ctx, tmp_path, which):
    """The top edge passes through each lifted vertex: at the vertex's column (one pixel inside the strip) the
    highest covered row is where the camera puts (x, height) of the file's sparse values, within 1.5 pixels.
    Without the sparse block all three would sit at y = 0."""
    _sparse_strip(tmp_path)
    image = render(ctx, write_scene(tmp_path, "sparse.glb", "{ unlit = true }"), which)
    covered = image[..., :3].max(axis=2) > 128
    for x, height in zip(SPARSE_X[1:], SPARSE_TOP, strict=True):
        column, row = pixel_of(float(x), float(height), SIZE)
        col = int(min(column, SIZE[0] - 1.5)) - (1 if x == SPARSE_X[-1] else 0)
        top = int(np.argmax(covered[:, col]))
        assert covered[:, col].any() and abs(top + 0.5 - row) <= 1.5, (which, x, height, top, row)


# -- helpers: colours as the output stores them ------------------------------------------------------------------

UNLIT = {"extensions": {"KHR_materials_unlit": {}}}  # colour = base colour exactly: no light model in the way


def srgb_encode(linear) -> np.ndarray:
    x = np.clip(np.asarray(linear, np.float64), 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055) * 255


def srgb_decode(byte) -> np.ndarray:
    c = np.asarray(byte, np.float64) / 255
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def at(image: np.ndarray, x: float, y: float) -> np.ndarray:
    """The RGB bytes of the pixel where the camera puts (x, y, 0)."""
    col, row = pixel_of(x, y, SIZE)
    return image[int(row), int(col), :3].astype(np.float64)


def assert_colour(image, x, y, linear_rgb, what, tol=3.0):
    got, want = at(image, x, y), srgb_encode(linear_rgb)
    assert np.abs(got - want).max() <= tol, (what, (x, y), got.tolist(), want.round(1).tolist())


def quad_primitive(g: GltfWriter, x0, y0, x1, y1, material=None, *, uvs=None, colors=None, flip=False) -> dict:
    attributes = {"POSITION": g.positions(quad(x0, y0, x1, y1))}
    if uvs is not None:
        attributes["TEXCOORD_0"] = g.accessor(np.asarray(uvs, np.float32))
    if colors is not None:
        attributes["COLOR_0"] = g.accessor(np.asarray(colors, np.float32))
    indices = QUAD_INDICES.reshape(-1, 3)[:, ::-1].ravel().copy() if flip else QUAD_INDICES
    prim = {"attributes": attributes, "indices": g.accessor(np.ascontiguousarray(indices))}
    if material is not None:
        prim["material"] = material
    return prim


# -- vertex colours x baseColorFactor ------------------------------------------------------------------------------

VERTEX_COLOURS = [(1.0, 0.0, 0.0, 1.0), (0.0, 1.0, 0.0, 1.0), (0.2, 0.4, 0.8, 1.0), (1.0, 1.0, 1.0, 1.0)]
FACTOR = (0.5, 1.0, 0.25, 1.0)


@pytest.mark.parametrize("which", PATHS)
def test_vertex_colours_times_base_colour_factor(ctx, tmp_path, which):
    """Four quads, each with one COLOR_0 value on its four vertices, one material with baseColorFactor FACTOR:
    each quad's centre shows colour x factor (linear), sRGB-encoded by the output."""
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": list(FACTOR)}, **UNLIT)
    corners = [(-1.8, 0.1), (0.1, 0.1), (-1.8, -1.8), (0.1, -1.8)]
    prims = [quad_primitive(g, x, y, x + 1.7, y + 1.7, mat, colors=[c] * 4)
             for (x, y), c in zip(corners, VERTEX_COLOURS, strict=True)]
    g.node(mesh=g.mesh(prims))
    g.write(tmp_path / "colours.glb")
    image = render(ctx, write_scene(tmp_path, "colours.glb"), which)
    for (x, y), c in zip(corners, VERTEX_COLOURS, strict=True):
        assert_colour(image, x + 0.85, y + 0.85, np.multiply(c, FACTOR)[:3], f"{which} COLOR_0 {c}")


# -- baseColorFactor x baseColorTexture (sRGB) ---------------------------------------------------------------------

TEXELS = np.array([[[200, 40, 10, 255], [30, 220, 90, 255]], [[60, 60, 250, 255], [250, 250, 250, 255]]], np.uint8)


@pytest.mark.parametrize("which", PATHS)
def test_base_colour_factor_times_srgb_texture(ctx, tmp_path, which):
    """A 2x2 texture (nearest, clamp) on a quad, factor FACTOR: each quarter shows decode(texel) x factor."""
    g = GltfWriter()
    tex = g.texture(TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33071))
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": list(FACTOR), "baseColorTexture": {"index": tex}},
                     **UNLIT)
    g.node(mesh=g.mesh([quad_primitive(g, -1.6, -1.6, 1.6, 1.6, mat, uvs=[[0, 1], [1, 1], [1, 0], [0, 0]])]))
    g.write(tmp_path / "textured.glb")
    image = render(ctx, write_scene(tmp_path, "textured.glb"), which)
    for row in range(2):
        for col in range(2):
            x, y = -0.8 + 1.6 * col, 0.8 - 1.6 * row  # texel row 0 is the top of the image (v = 0)
            want = srgb_decode(TEXELS[row, col, :3]) * FACTOR[:3]
            assert_colour(image, x, y, want, f"{which} texel {row},{col}")


# -- each primitive its own material -------------------------------------------------------------------------------

PRIMITIVE_COLOURS = [(0.9, 0.1, 0.1), (0.1, 0.8, 0.2), (0.2, 0.3, 0.9)]


@pytest.mark.parametrize("which", PATHS)
def test_each_primitive_draws_with_its_own_material(ctx, tmp_path, which):
    """Three primitives of one mesh, materials 2, 0, 1 (out of order on purpose): each quad its material's colour."""
    g = GltfWriter()
    mats = [g.material(pbrMetallicRoughness={"baseColorFactor": [*c, 1.0]}, **UNLIT) for c in PRIMITIVE_COLOURS]
    xs = (-1.8, -0.55, 0.7)
    order = (2, 0, 1)
    g.node(mesh=g.mesh([quad_primitive(g, x, -1, x + 1.1, 1, mats[m]) for x, m in zip(xs, order, strict=True)]))
    g.write(tmp_path / "materials.glb")
    image = render(ctx, write_scene(tmp_path, "materials.glb"), which)
    for x, m in zip(xs, order, strict=True):
        assert_colour(image, x + 0.55, 0.0, PRIMITIVE_COLOURS[m], f"{which} primitive with material {m}")


def test_a_scene_material_still_overrides_the_file(ctx, tmp_path):
    """material = { ... } in the scene: every primitive draws with it, the file's colours are not used."""
    g = GltfWriter()
    mats = [g.material(pbrMetallicRoughness={"baseColorFactor": [*c, 1.0]}, **UNLIT) for c in PRIMITIVE_COLOURS]
    g.node(mesh=g.mesh([quad_primitive(g, x, -1, x + 1.1, 1, m) for x, m in zip((-1.8, -0.55, 0.7), mats,
                                                                               strict=True)]))
    g.write(tmp_path / "materials.glb")
    image = render(ctx, write_scene(tmp_path, "materials.glb", "{ unlit = true, albedo_color = [0.5, 0.5, 0.5] }"),
                   "wgpu")
    for x in (-1.25, 0.0, 1.25):
        assert_colour(image, x, 0.0, (0.5, 0.5, 0.5), "scene material")


# -- each texture its own sampler: per-axis wrap -------------------------------------------------------------------

WRAP_MODES = {10497: lambda t: t - np.floor(t), 33071: lambda t: np.clip(t, 0.0, 1.0),
              33648: lambda t: 1.0 - np.abs((t - 2.0 * np.floor(t / 2.0)) - 1.0)}


@pytest.mark.parametrize("wrap", [(10497, 33071), (33648, 10497), (33071, 33648)], ids=["repeat-clamp",
                                                                                          "mirror-repeat",
                                                                                          "clamp-mirror"])
@pytest.mark.parametrize("which", PATHS)
def test_per_axis_wrap_modes(ctx, tmp_path, which, wrap):
    """UVs run from -1 to 2 across a quad (u with x, v downwards), nearest filtering on a 2x2 texture: at 36
    points (texel centres of the 3x3 tiles) the texel is the one the file's wrapS / wrapT select, computed here
    with each mode's formula."""
    wrap_s, wrap_t = wrap
    g = GltfWriter()
    tex = g.texture(TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=wrap_s, wrapT=wrap_t))
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex}}, **UNLIT)
    uvs = [[-1, 2], [2, 2], [2, -1], [-1, -1]]  # quad corners: bottom-left, bottom-right, top-right, top-left
    g.node(mesh=g.mesh([quad_primitive(g, -1.5, -1.5, 1.5, 1.5, mat, uvs=uvs)]))
    g.write(tmp_path / "wrap.glb")
    image = render(ctx, write_scene(tmp_path, "wrap.glb"), which)
    for u in np.arange(-0.75, 2.0, 0.5):
        for v in np.arange(-0.75, 2.0, 0.5):
            x, y = u - 0.5, 0.5 - v  # the quad maps x = -1.5..1.5 to u = -1..2 and y = 1.5..-1.5 to v = -1..2
            s, t = WRAP_MODES[wrap_s](u), WRAP_MODES[wrap_t](v)
            texel = TEXELS[min(int(t * 2), 1), min(int(s * 2), 1), :3]
            assert_colour(image, x, y, srgb_decode(texel), f"{which} uv ({u}, {v}) wrap {wrap}")


# -- doubleSided ---------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("which", PATHS)
def test_double_sided_faces_are_drawn_from_behind(ctx, tmp_path, which):
    """Two quads wound clockwise as seen from the camera (their back faces): the doubleSided one (left, red) is
    drawn, the single-sided one (right, green) is culled, leaving the black background."""
    g = GltfWriter()
    two = g.material(doubleSided=True, pbrMetallicRoughness={"baseColorFactor": [1, 0, 0, 1]}, **UNLIT)
    one = g.material(pbrMetallicRoughness={"baseColorFactor": [0, 1, 0, 1]}, **UNLIT)
    g.node(mesh=g.mesh([quad_primitive(g, -1.8, -1, -0.2, 1, two, flip=True),
                        quad_primitive(g, 0.2, -1, 1.8, 1, one, flip=True)]))
    g.write(tmp_path / "sides.glb")
    image = render(ctx, write_scene(tmp_path, "sides.glb"), which)
    assert_colour(image, -1.0, 0.0, (1, 0, 0), f"{which} double-sided back face")
    assert_colour(image, 1.0, 0.0, (0, 0, 0), f"{which} single-sided back face (culled)")


# -- alphaMode MASK ------------------------------------------------------------------------------------------------

ALPHAS = np.array([[[255, 255, 255, 64], [255, 255, 255, 191]]], np.uint8)  # alpha 0.251 | 0.749


@pytest.mark.parametrize("cutoff", [0.5, 0.2, 0.8])
@pytest.mark.parametrize("which", PATHS)
def test_alpha_mask_discards_below_the_cutoff(ctx, tmp_path, which, cutoff):
    """A 2x1 texture with alpha 64/255 (left) and 191/255 (right), alphaMode MASK: a half is drawn (white) exactly
    when its alpha is at least alphaCutoff, else the black background shows."""
    g = GltfWriter()
    tex = g.texture(ALPHAS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33071))
    mat = g.material(alphaMode="MASK", alphaCutoff=cutoff, pbrMetallicRoughness={"baseColorTexture": {"index": tex}},
                     **UNLIT)
    g.node(mesh=g.mesh([quad_primitive(g, -1.6, -1.0, 1.6, 1.0, mat, uvs=[[0, 1], [1, 1], [1, 0], [0, 0]])]))
    g.write(tmp_path / "mask.glb")
    image = render(ctx, write_scene(tmp_path, "mask.glb"), which)
    for x, alpha in ((-0.8, ALPHAS[0, 0, 3] / 255), (0.8, ALPHAS[0, 1, 3] / 255)):
        want = (1, 1, 1) if alpha >= cutoff else (0, 0, 0)
        assert_colour(image, x, 0.0, want, f"{which} alpha {alpha:.3f} cutoff {cutoff}")
        if alpha >= cutoff:  # what a MASK keeps is opaque
            col, row = pixel_of(x, 0.0, SIZE)
            assert image[int(row), int(col), 3] == 255, (which, alpha, cutoff)


@pytest.mark.parametrize("which", PATHS)
def test_opaque_ignores_alpha(ctx, tmp_path, which):
    """alphaMode OPAQUE (the default) with texels of alpha 64/255 and 191/255 and a factor alpha of 0.5: the colour
    is drawn and the output's alpha is 255 (glTF: the alpha value is ignored)."""
    g = GltfWriter()
    tex = g.texture(ALPHAS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33071))
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex}, "baseColorFactor": [1, 1, 1, 0.5]},
                     **UNLIT)
    g.node(mesh=g.mesh([quad_primitive(g, -1.6, -1.0, 1.6, 1.0, mat, uvs=[[0, 1], [1, 1], [1, 0], [0, 0]])]))
    g.write(tmp_path / "opaque.glb")
    image = render(ctx, write_scene(tmp_path, "opaque.glb"), which)
    for x in (-0.8, 0.8):
        assert_colour(image, x, 0.0, (1, 1, 1), f"{which} opaque colour")
        col, row = pixel_of(x, 0.0, SIZE)
        assert image[int(row), int(col), 3] == 255, which


# -- node hierarchy ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("which", PATHS)
def test_node_hierarchy_places_the_quad(ctx, tmp_path, which):
    """A unit quad under a child node (rotation 90 degrees about z, scale 0.5) under a parent (translation
    (0.5, -0.25, 0)): its corners land at parent @ child @ corner (composed here); the covered pixels span their
    projection, within 1 pixel."""
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [1, 1, 1, 1]}, **UNLIT)
    s = float(np.sin(np.pi / 4))
    child = g.node(mesh=g.mesh([quad_primitive(g, 0, 0, 2, 1, mat)]), rotation=[0, 0, s, s], scale=[0.5] * 3)
    parent = g.node(children=[child], translation=[0.5, -0.25, 0])
    g.write(tmp_path / "tree.glb", roots=[parent])
    image = render(ctx, write_scene(tmp_path, "tree.glb"), which)
    corners = quad(0, 0, 2, 1)[:, :2] * 0.5
    world = np.c_[-corners[:, 1], corners[:, 0]] + [0.5, -0.25]  # rotate 90 degrees: (x, y) -> (-y, x)
    cols, rows = zip(*(pixel_of(x, y, SIZE) for x, y in world), strict=True)
    covered = np.argwhere(image[..., :3].max(axis=2) > 128)
    assert abs(covered[:, 1].min() - min(cols)) <= 1 and abs(covered[:, 1].max() + 1 - max(cols)) <= 1, which
    assert abs(covered[:, 0].min() - min(rows)) <= 1 and abs(covered[:, 0].max() + 1 - max(rows)) <= 1, which


# -- alphaMode BLEND -----------------------------------------------------------------------------------------------

@pytest.mark.parametrize("which", PATHS)
def test_alpha_blend_is_drawn_over_the_opaque_draws(ctx, tmp_path, which):
    """A BLEND quad (red, alpha 0.25) in front of an OPAQUE blue one, the blended primitive FIRST in the file:
    blended draws go last, so the overlap is 0.25 red + 0.75 blue (source-over, in linear light: the sRGB target
    blends before it encodes); beside the opaque quad the background shows through: 0.25 red."""
    g = GltfWriter()
    glass = g.material(alphaMode="BLEND", pbrMetallicRoughness={"baseColorFactor": [1, 0, 0, 0.25]}, **UNLIT)
    wall = g.material(pbrMetallicRoughness={"baseColorFactor": [0, 0, 1, 1]}, **UNLIT)
    front = {"attributes": {"POSITION": g.positions(quad(-1.5, -1, 1.5, 1, z=0.5))},
             "indices": g.accessor(QUAD_INDICES), "material": glass}
    g.node(mesh=g.mesh([front, quad_primitive(g, -1.8, -1.8, 0, 1.8, wall)]))
    g.write(tmp_path / "blend.glb")
    image = render(ctx, write_scene(tmp_path, "blend.glb"), which)
    assert_colour(image, -0.4, 0.0, (0.25, 0.0, 0.75), f"{which} blended over opaque")
    assert_colour(image, 0.6, 0.0, (0.25, 0.0, 0.0), f"{which} blended over the background")


# -- a lit double-sided surface seen from behind ------------------------------------------------------------------

@pytest.mark.parametrize("which", PATHS)
def test_double_sided_back_face_is_lit_with_its_normal_turned(ctx, tmp_path, which):
    """A lit quad whose front faces away from the camera, doubleSided, albedo a, metallicFactor 0, roughnessFactor
    1; a directional light shining along -z (from behind the camera). At the centre l = v = h = n' (the turned
    normal), so glTF's metallic-roughness BRDF (Appendix B; alpha = 1: D = 1 / pi, V = 0.5 / (1 + 1), F = 0.04)
    gives L = ambient * a + pi * (0.96 * a / pi + 0.04 * D * V) = ambient * a + 0.96 a + 0.01: without the turn n.l
    would be -1 and only ambient * a would remain."""
    albedo = np.array([0.4, 0.3, 0.2])
    g = GltfWriter()
    mat = g.material(doubleSided=True, pbrMetallicRoughness={"baseColorFactor": [*albedo, 1], "metallicFactor": 0,
                                                             "roughnessFactor": 1.0})
    g.node(mesh=g.mesh([quad_primitive(g, -1, -1, 1, 1, mat, flip=True)]))
    g.write(tmp_path / "lit.glb")
    light = '\n[[lights]]\ntype = "directional"\ndirection = [0, 0, -1]\n'
    image = render(ctx, write_scene(tmp_path, "lit.glb", extra=light), which)
    ambient = np.array([0.03, 0.03, 0.035])  # course.shading.AMBIENT, written in docs/scenes.md's shading model
    want = ambient * albedo + 0.96 * albedo + 0.04 * np.pi * (1 / np.pi) * (0.5 / 2)
    assert_colour(image, 0.0, 0.0, want, f"{which} lit back face")


# -- what --explain says -------------------------------------------------------------------------------------------

def test_explain_lists_what_was_taken_and_what_was_ignored(tmp_path, capsys):
    """A material with emissive, occlusion on texCoord 1 (kept lit without lights: it scales the ambient term; the
    mesh's second coordinate slot), metalness and KHR_materials_sheen; extensionsUsed lists sheen and
    KHR_materials_unlit (supported): --explain names what was taken and every ignored feature."""
    from wgpurender.cli import main

    g = GltfWriter()
    tex = g.texture(TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33648))
    mat = g.material(name="coat", emissiveFactor=[1, 0, 0], occlusionTexture={"index": tex, "texCoord": 1},
                     pbrMetallicRoughness={"baseColorTexture": {"index": tex}, "metallicFactor": 1.0},
                     extensions={"KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1]}})
    prim = quad_primitive(g, -1, -1, 1, 1, mat, uvs=[[0, 1], [1, 1], [1, 0], [0, 0]])
    prim["attributes"]["TEXCOORD_1"] = prim["attributes"]["TEXCOORD_2"] = prim["attributes"]["TEXCOORD_0"]
    g.node(mesh=g.mesh([prim, {"attributes": {"POSITION": g.positions(quad(0, 0, 1, 1))}, "mode": 1}]))
    g.doc["extensionsUsed"] = ["KHR_materials_sheen", "KHR_materials_unlit"]
    g.write(tmp_path / "coat.glb")
    code = main(["render", str(write_scene(tmp_path, "coat.glb")), "--explain"])
    out = capsys.readouterr().out
    assert code == 0
    assert "from the model file" in out and "'coat'" in out
    assert "albedo_map" in out and "wrap clamp-to-edge/mirror-repeat" in out and "nearest/nearest" in out
    assert "emissiveFactor (1.0, 0.0, 0.0)" in out  # taken; without lights occlusion still scales the ambient term:
    assert "occlusion map scales the ambient term: it keeps the lit variant" in out and "occlusion_map" in out
    for ignored in ("KHR_materials_sheen: ignored",
                    "attribute(s) TEXCOORD_2 ignored", "LINES primitive drawn unlit", "occlusion_map_uv1",
                    "extensionsUsed KHR_materials_sheen: ignored"):
        assert ignored in out, ignored
    assert "KHR_materials_unlit: ignored" not in out and "TEXCOORD_1 ignored" not in out
    assert "occlusion_map" in out and "(TEXCOORD_1: coordinate slot 1)" in out  # texCoord 1: the second slot
    assert "metallicFactor 1" in out and "metalness" not in out  # metalness is taken: the metallic-roughness model
    assert "pbr: " in out and "glTF metallic-roughness material" in out


def test_cli_refuses_gltf_1_and_unknown_required_extensions(tmp_path, capsys):
    """One line each, exit 2: the version, and the extension by name."""
    import json

    from wgpurender.cli import main

    (tmp_path / "old.gltf").write_text(json.dumps({"asset": {"version": "1.0"}, "scene": "defaultScene"}))
    g = GltfWriter()
    g.node(mesh=g.mesh([quad_primitive(g, -1, -1, 1, 1)]))
    g.doc["extensionsRequired"] = g.doc["extensionsUsed"] = ["KHR_texture_basisu"]
    g.write(tmp_path / "packed.glb")
    for model, needle in (("old.gltf", "glTF 1.0 is not supported (glTF 2.0 only)"),
                          ("packed.glb", "KHR_texture_basisu")):
        scene = write_scene(tmp_path, model)
        code = main(["render", str(scene), "-o", str(tmp_path / "out.png")])
        err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
        assert code == 2 and len(err) == 1 and needle in err[0], err


# -- emissive and occlusion ----------------------------------------------------------------------------------------

EMISSIVE = (0.2, 0.5, 0.1)
EMISSIVE_TEXELS = np.array([[[255, 128, 255, 255], [40, 255, 200, 255]]], np.uint8)


@pytest.mark.parametrize("which", PATHS)
def test_emissive_factor_times_texture_is_added(ctx, tmp_path, which):
    """A black lit material (no lights: only the ambient term, ambient x black = 0) with emissiveFactor EMISSIVE
    and a 2x1 sRGB emissiveTexture (nearest): each half shows EMISSIVE x decode(texel)."""
    g = GltfWriter()
    tex = g.texture(EMISSIVE_TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33071))
    mat = g.material(emissiveFactor=list(EMISSIVE), emissiveTexture={"index": tex},
                     pbrMetallicRoughness={"baseColorFactor": [0, 0, 0, 1]})
    g.node(mesh=g.mesh([quad_primitive(g, -1.6, -1, 1.6, 1, mat, uvs=[[0, 1], [1, 1], [1, 0], [0, 0]])]))
    g.write(tmp_path / "glow.glb")
    image = render(ctx, write_scene(tmp_path, "glow.glb"), which)
    for x, texel in ((-0.8, EMISSIVE_TEXELS[0, 0, :3]), (0.8, EMISSIVE_TEXELS[0, 1, :3])):
        assert_colour(image, x, 0.0, np.multiply(EMISSIVE, srgb_decode(texel)), f"{which} emissive {texel}")


OCCLUSION_TEXELS = np.array([[[255, 0, 0, 255], [64, 0, 0, 255]]], np.uint8)  # R = 1 | 64/255 (linear data)


@pytest.mark.parametrize("lights", ["back_light", "no_lights"])
@pytest.mark.parametrize("which", PATHS)
def test_occlusion_scales_the_ambient_term(ctx, tmp_path, which, lights):
    """A white lit quad, a directional light travelling along +z (it reaches only the back: n.l < 0, no direct
    light) or no light at all (the material stays lit: the occlusion map shapes its ambient term),
    occlusionTexture strength 0.8: each half shows ambient x (1 + 0.8 (R - 1)), R the texel's linear red."""
    strength = 0.8
    g = GltfWriter()
    tex = g.texture(OCCLUSION_TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33071))
    mat = g.material(occlusionTexture={"index": tex, "strength": strength},
                     pbrMetallicRoughness={"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0})
    g.node(mesh=g.mesh([quad_primitive(g, -1.6, -1, 1.6, 1, mat, uvs=[[0, 1], [1, 1], [1, 0], [0, 0]])]))
    g.write(tmp_path / "ao.glb")
    light = '\n[[lights]]\ntype = "directional"\ndirection = [0, 0, 1]\n' if lights == "back_light" else ""
    image = render(ctx, write_scene(tmp_path, "ao.glb", extra=light), which)
    ambient = np.array([0.03, 0.03, 0.035])  # course.shading.AMBIENT
    for x, red in ((-0.8, OCCLUSION_TEXELS[0, 0, 0] / 255), (0.8, OCCLUSION_TEXELS[0, 1, 0] / 255)):
        assert_colour(image, x, 0.0, ambient * (1 + strength * (red - 1)), f"{which} occlusion {red:.3f}", tol=2)


# -- an OBJ's MTL ----------------------------------------------------------------------------------------------------

MTL_KD = (0.5, 0.25, 1.0)
MTL_TEXEL = np.array([[[200, 180, 90, 255]]], np.uint8)


@pytest.mark.parametrize("which", PATHS)
def test_obj_mtl_colour_times_texture(ctx, tmp_path, which):
    """An OBJ quad whose MTL says Kd MTL_KD, map_Kd a 1x1 sRGB texel, illum 0 (colour only), and no scene
    material: the quad shows Kd x decode(texel). (OBJ stores v = 0 at the bottom: one texel reads the same.)"""
    from PIL import Image

    Image.fromarray(MTL_TEXEL, "RGBA").save(tmp_path / "texel.png")
    (tmp_path / "quad.mtl").write_text(f"newmtl paint\nKd {MTL_KD[0]} {MTL_KD[1]} {MTL_KD[2]}\nillum 0\n"
                                       "map_Kd texel.png\n")
    (tmp_path / "quad.obj").write_text("mtllib quad.mtl\nv -1.5 -1 0\nv 1.5 -1 0\nv 1.5 1 0\nv -1.5 1 0\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl paint\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
    image = render(ctx, write_scene(tmp_path, "quad.obj"), which)
    assert_colour(image, 0.0, 0.0, np.multiply(MTL_KD, srgb_decode(MTL_TEXEL[0, 0, :3])), f"{which} MTL")
