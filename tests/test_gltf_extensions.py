"""glTF extensions drawn as the file means them, on both paths, checked against the numbers written into the file.

Each model is written here (tests/gltf_gen.py; Draco data by DracoPy's encoder, meshopt data by meshoptimizer's
encoder, both independent of the loader) after the Khronos samples that test the same feature
(TextureTransformTest, MultiUVTest, SimpleInstancing, MorphPrimitivesTest, UnlitTest); every expectation is
computed from the file's numbers and the camera (gltf_gen.pixel_of), never from the loader under test.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from gltf_gen import QUAD_INDICES, GltfWriter, pixel_of, quad
from test_gltf_render import PATHS, SIZE, UNLIT, assert_colour, render, srgb_decode, write_scene

from wgpurender.core.errors import UserError
from wgpurender.core.models.mesh import load_mesh

# a 2x2 texture, texel (row, col) a distinct colour; nearest filtering, so each quarter of UV space is one colour
TEXELS = np.array([[[230, 30, 30, 255], [30, 200, 40, 255]], [[40, 60, 230, 255], [240, 240, 240, 255]]], np.uint8)
QUAD_UV = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)  # glTF: v = 0 at the top
HALF = 1.6  # the quad spans -HALF..HALF in x and y


def textured_quad(g: GltfWriter, texture_info: dict, uv_sets: dict[str, np.ndarray], wrap: int = 10497) -> None:
    """One unlit quad whose base colour texture is TEXELS through ``texture_info`` (index filled in)."""
    tex = g.texture(TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=wrap, wrapT=wrap))
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex, **texture_info}}, **UNLIT)
    attributes = {"POSITION": g.positions(quad(-HALF, -HALF, HALF, HALF))}
    attributes.update({name: g.accessor(np.asarray(uv, np.float32)) for name, uv in uv_sets.items()})
    g.node(mesh=g.mesh([{"attributes": attributes, "indices": g.accessor(QUAD_INDICES), "material": mat}]))


def expected_texels(image, transform, what: str) -> int:
    """At a grid of points on the quad: the texel the spec's transform selects (repeat wrap), where it is not
    within 0.06 of a texel edge. uv at (x, y) is linear: u = (x + H) / 2H, v = (H - y) / 2H. Returns the count."""
    ox, oy = transform.get("offset", (0, 0))
    sx, sy = transform.get("scale", (1, 1))
    r = transform.get("rotation", 0.0)
    checked = 0
    for x in np.linspace(-1.4, 1.4, 9):
        for y in np.linspace(-1.4, 1.4, 9):
            u, v = (x + HALF) / (2 * HALF), (HALF - y) / (2 * HALF)
            # KHR_texture_transform: T(offset) R(rotation) S(scale), rotation matrix [[cos, sin], [-sin, cos]]
            tu = ox + math.cos(r) * sx * u + math.sin(r) * sy * v
            tv = oy - math.sin(r) * sx * u + math.cos(r) * sy * v
            fu, fv = (tu % 1.0) * 2, (tv % 1.0) * 2
            if min(abs(fu - round(fu)), abs(fv - round(fv))) < 0.12:
                continue
            texel = TEXELS[int(fv) % 2, int(fu) % 2, :3]
            assert_colour(image, x, y, srgb_decode(texel), f"{what} uv ({tu:.2f}, {tv:.2f})", tol=4.0)
            checked += 1
    return checked


TRANSFORMS = {"offset": {"offset": [0.5, 0.0]}, "scale": {"scale": [1.5, 0.5]},
              "rotation": {"rotation": 0.392699}, "all": {"offset": [0.25, -0.3], "rotation": 1.1, "scale": [2, 1.5]}}


@pytest.mark.parametrize("name", list(TRANSFORMS))
@pytest.mark.parametrize("which", PATHS)
def test_texture_transform(ctx, tmp_path, which, name):
    """KHR_texture_transform (TextureTransformTest's offset, rotation, scale and all three): each point shows the
    texel the spec's matrix picks; an untransformed render fails at most of them."""
    g = GltfWriter()
    textured_quad(g, {"extensions": {"KHR_texture_transform": TRANSFORMS[name]}}, {"TEXCOORD_0": QUAD_UV})
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["KHR_texture_transform", "KHR_materials_unlit"]
    g.write(tmp_path / "tt.glb")
    image = render(ctx, write_scene(tmp_path, "tt.glb"), which)
    assert expected_texels(image, TRANSFORMS[name], f"{which} {name}") >= 20


@pytest.mark.parametrize("which", PATHS)
def test_texcoord_1_and_the_transform_override(ctx, tmp_path, which):
    """MultiUVTest's point: the texture samples TEXCOORD_1 (TEXCOORD_0 is all zeros: texel (0, 0) everywhere).
    Once via textureInfo.texCoord 1, once via KHR_texture_transform's texCoord override (textureInfo says 0)."""
    zeros = np.zeros((4, 2), np.float32)
    for label, info in (("texCoord", {"texCoord": 1}),
                        ("override", {"extensions": {"KHR_texture_transform": {"texCoord": 1, "offset": [0.5, 0]}}})):
        g = GltfWriter()
        textured_quad(g, info, {"TEXCOORD_0": zeros, "TEXCOORD_1": QUAD_UV})
        g.write(tmp_path / f"{label}.glb")
        image = render(ctx, write_scene(tmp_path, f"{label}.glb"), which)
        transform = info.get("extensions", {}).get("KHR_texture_transform", {})
        assert expected_texels(image, transform, f"{which} {label}") >= 20


@pytest.mark.parametrize("which", PATHS)
def test_quantized_positions_normals_and_texcoords(ctx, tmp_path, which):
    """KHR_mesh_quantization as gltfpack writes it: POSITION int16 (not normalized) with the node's scale undoing
    the quantization, NORMAL int8 normalized, TEXCOORD_0 uint8 (not normalized: 0 or 1). The quad's edges land
    where scale x integer puts them; the texture's quarters show."""
    g = GltfWriter()
    tex = g.texture(TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33071))
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex}}, **UNLIT)
    step = 1 / 1000  # one integer unit
    ints = np.array([[-1200, -1000, 0], [1400, -1000, 0], [1400, 1300, 0], [-1200, 1300, 0]], np.int16)
    pos = g.accessor(ints)
    g.doc["accessors"][pos].update(min=ints.min(0).tolist(), max=ints.max(0).tolist())
    attributes = {"POSITION": pos, "NORMAL": g.accessor(np.tile(np.int8([0, 0, 127]), (4, 1)), normalized=True),
                  "TEXCOORD_0": g.accessor(QUAD_UV.astype(np.uint8))}
    g.node(mesh=g.mesh([{"attributes": attributes, "indices": g.accessor(QUAD_INDICES), "material": mat}]),
           scale=[step, step, step])
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["KHR_mesh_quantization"]
    g.write(tmp_path / "q.glb")
    image = render(ctx, write_scene(tmp_path, "q.glb"), which)
    x0, y0, x1, y1 = -1.2, -1.0, 1.4, 1.3
    covered = image[..., :3].max(axis=2) > 20
    for x, y, inside in ((x0 + 0.05, 0, True), (x0 - 0.08, 0, False), (x1 - 0.05, 0, True), (x1 + 0.08, 0, False),
                         (0, y1 - 0.05, True), (0, y1 + 0.08, False), (0, y0 + 0.05, True), (0, y0 - 0.08, False)):
        col, row = pixel_of(x, y, SIZE)
        assert covered[int(row), int(col)] == inside, (which, x, y, inside)
    for row in range(2):
        for col in range(2):
            x = x0 + (x1 - x0) * (0.25 + 0.5 * col)
            y = y1 - (y1 - y0) * (0.25 + 0.5 * row)
            assert_colour(image, x, y, srgb_decode(TEXELS[row, col, :3]), f"{which} quantized texel {row},{col}")


def test_quantized_types_need_the_extension_in_extensions_used(tmp_path):
    """Without KHR_mesh_quantization in extensionsUsed an int16 POSITION breaks glTF 2.0's table: one line."""
    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.accessor(quad(0, 0, 1, 1).astype(np.int16))},
                         "indices": g.accessor(QUAD_INDICES)}]))
    with pytest.raises(UserError, match="POSITION must have componentType FLOAT"):
        load_mesh(g.write(tmp_path / "q.glb"))


EMISSIVE = (0.1, 0.05, 0.02)


@pytest.mark.parametrize("which", PATHS)
def test_emissive_strength_multiplies_the_factor(ctx, tmp_path, which):
    """KHR_materials_emissive_strength 4 on a black lit material without lights: the quad shows 4 x the factor."""
    g = GltfWriter()
    mat = g.material(emissiveFactor=list(EMISSIVE), pbrMetallicRoughness={"baseColorFactor": [0, 0, 0, 1]},
                     extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}})
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-1, -1, 1, 1))},
                         "indices": g.accessor(QUAD_INDICES), "material": mat}]))
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["KHR_materials_emissive_strength"]
    g.write(tmp_path / "e.glb")
    image = render(ctx, write_scene(tmp_path, "e.glb"), which)
    assert_colour(image, 0, 0, np.multiply(EMISSIVE, 4.0), f"{which} emissive x strength")


@pytest.mark.parametrize("which", PATHS)
def test_required_unlit_is_drawn_unlit(ctx, tmp_path, which):
    """UnlitTest's case: a file that lists KHR_materials_unlit in extensionsRequired renders its base colour."""
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [0.2, 0.6, 0.9, 1]}, **UNLIT)
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-1, -1, 1, 1))},
                         "indices": g.accessor(QUAD_INDICES), "material": mat}]))
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["KHR_materials_unlit"]
    g.write(tmp_path / "u.glb")
    assert_colour(render(ctx, write_scene(tmp_path, "u.glb"), which), 0, 0, (0.2, 0.6, 0.9), f"{which} unlit")


def top_edge(image, x: float) -> float:
    """The y (scene units) of the highest covered pixel in the column where the camera puts x."""
    col, _ = pixel_of(x, 0, SIZE)
    covered = image[:, int(col), :3].max(axis=1) > 20
    row = int(np.argmax(covered)) + 0.5
    return (1 - 2 * row / SIZE[1]) * 2


@pytest.mark.parametrize("which", PATHS)
def test_default_morph_weights(ctx, tmp_path, which):
    """MorphPrimitivesTest's point: two targets lift the top edge by 1.0 and 0.6 (POSITION deltas); mesh.weights
    (0.5, 0.25) put it at -0.6 + 0.5 + 0.15; a second node's own weights (1, 1) override the mesh's."""
    g = GltfWriter()
    base = quad(-0.8, -1.5, 0.8, -0.6)
    up1 = np.float32([[0, 0, 0], [0, 0, 0], [0, 1.0, 0], [0, 1.0, 0]])
    up2 = np.float32([[0, 0, 0], [0, 0, 0], [0, 0.6, 0], [0, 0.6, 0]])
    prim = {"attributes": {"POSITION": g.positions(base)}, "indices": g.accessor(QUAD_INDICES),
            "targets": [{"POSITION": g.positions(up1)}, {"POSITION": g.positions(up2)}]}
    mesh = g.mesh([prim])
    g.doc["meshes"][mesh]["weights"] = [0.5, 0.25]
    g.node(mesh=mesh, translation=[-1.0, 0, 0])
    g.node(mesh=mesh, translation=[1.0, 0, 0], weights=[1.0, 1.0])
    g.write(tmp_path / "morph.glb")
    image = render(ctx, write_scene(tmp_path, "morph.glb", "{ unlit = true }"), which)
    for x, want in ((-1.0, -0.6 + 0.5 * 1.0 + 0.25 * 0.6), (1.0, -0.6 + 1.0 + 0.6)):
        assert abs(top_edge(image, x) - want) <= 2 * 4 / SIZE[1] + 1e-6, (which, x, top_edge(image, x), want)


INSTANCES_T = np.float32([[-1.2, 0.9, 0], [1.1, 0.8, 0], [-1.0, -1.0, 0], [1.0, -1.0, 0]])
INSTANCES_S = np.float32([[1, 1, 1], [1.5, 0.5, 1], [0.5, 0.5, 1], [1.4, 0.6, 1]])
INSTANCES_R = np.float32([[0, 0, 0, 1], [0, 0, 0, 1], [0, 0, 0, 1],
                          [0, 0, math.sin(math.pi / 8), math.cos(math.pi / 8)]])  # the last turned 45 degrees


@pytest.mark.parametrize("which", PATHS)
def test_gpu_instancing_places_every_instance(ctx, tmp_path, which):
    """SimpleInstancing's point: one 0.6-wide quad, EXT_mesh_gpu_instancing with 4 TRS instances under a node
    translated by (0, 0.05): every instance's corners (node @ T R S @ corner) are covered, its outside is not."""
    g = GltfWriter()
    mesh = g.mesh([{"attributes": {"POSITION": g.positions(quad(-0.3, -0.3, 0.3, 0.3))},
                    "indices": g.accessor(QUAD_INDICES)}])
    attrs = {"TRANSLATION": g.accessor(INSTANCES_T), "SCALE": g.accessor(INSTANCES_S),
             "ROTATION": g.accessor(INSTANCES_R)}
    g.node(mesh=mesh, translation=[0, 0.05, 0], extensions={"EXT_mesh_gpu_instancing": {"attributes": attrs}})
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["EXT_mesh_gpu_instancing"]
    g.write(tmp_path / "inst.glb")
    image = render(ctx, write_scene(tmp_path, "inst.glb", "{ unlit = true }"), which)
    covered = image[..., :3].max(axis=2) > 20
    for t, s, q in zip(INSTANCES_T, INSTANCES_S, INSTANCES_R, strict=True):
        angle = 2 * math.atan2(q[2], q[3])
        for cx, cy, inside in ((0.8, 0.8, True), (-0.8, 0.8, True), (1.3, 0, False), (0, -1.3, False)):
            lx, ly = cx * 0.3 * s[0], cy * 0.3 * s[1]
            x = t[0] + lx * math.cos(angle) - ly * math.sin(angle)
            y = 0.05 + t[1] + lx * math.sin(angle) + ly * math.cos(angle)
            col, row = pixel_of(x, y, SIZE)
            assert covered[int(row), int(col)] == inside, (which, t.tolist(), cx, cy)
    assert covered.sum() > 0.9 * sum(0.36 * s[0] * s[1] for s in INSTANCES_S) * (SIZE[0] / 4) ** 2


def _draco_quad(tmp_path):
    DracoPy = pytest.importorskip("DracoPy")
    positions = quad(-HALF, -HALF, HALF, HALF).astype(np.float64)
    blob = DracoPy.encode(positions, QUAD_INDICES.reshape(-1, 3).astype(np.uint32), tex_coord=QUAD_UV.astype(
        np.float64), quantization_bits=14, preserve_order=True)
    decoded = DracoPy.decode(blob)  # the unique ids Draco gave each attribute, read from its own decoder
    ids = {a["attribute_type"]: a["unique_id"] for a in decoded.attributes}
    g = GltfWriter()
    tex = g.texture(TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33071))
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex}}, **UNLIT)
    view = g.view(blob)
    acc = [{"componentType": 5126, "count": 4, "type": "VEC3", "min": [-HALF, -HALF, 0], "max": [HALF, HALF, 0]},
           {"componentType": 5126, "count": 4, "type": "VEC2"}, {"componentType": 5123, "count": 6, "type": "SCALAR"}]
    first = len(g.doc["accessors"])
    g.doc["accessors"] += acc
    ext = {"bufferView": view, "attributes": {"POSITION": ids[0], "TEXCOORD_0": ids[3]}}  # 0 POSITION, 3 TEX_COORD
    g.node(mesh=g.mesh([{"attributes": {"POSITION": first, "TEXCOORD_0": first + 1}, "indices": first + 2,
                         "material": mat, "extensions": {"KHR_draco_mesh_compression": ext}}]))
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    return g.write(tmp_path / "draco.glb")


def quarters(image, which: str, what: str) -> None:
    for row in range(2):
        for col in range(2):
            x, y = -0.8 + 1.6 * col, 0.8 - 1.6 * row
            assert_colour(image, x, y, srgb_decode(TEXELS[row, col, :3]), f"{which} {what} texel {row},{col}")


@pytest.mark.parametrize("which", PATHS)
def test_draco_compressed_quad(ctx, tmp_path, which):
    """KHR_draco_mesh_compression (data from Google's encoder via DracoPy): the quad's four texture quarters."""
    _draco_quad(tmp_path)
    quarters(render(ctx, write_scene(tmp_path, "draco.glb"), which), which, "draco")


def _meshopt_quad(tmp_path, filtered: bool = False):
    meshopt = pytest.importorskip("meshoptimizer")
    g = GltfWriter()
    tex = g.texture(TEXELS, g.sampler(magFilter=9728, minFilter=9728, wrapS=33071, wrapT=33071))
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex}}, **UNLIT)
    vertices = np.concatenate([quad(-HALF, -HALF, HALF, HALF), QUAD_UV, np.zeros((4, 3), np.float32)], axis=1)
    vertices = np.ascontiguousarray(vertices, np.float32)  # 32-byte vertices: position, uv, padding
    packed = bytes(meshopt.encode_vertex_buffer(vertices, 4, 32))
    indices = bytes(meshopt.encode_index_buffer(QUAD_INDICES.astype(np.uint32), 6, 2))
    compressed = len(g.data)
    g.data += packed + b"\0" * (-len(packed) % 4)
    index_at = len(g.data)
    g.data += indices + b"\0" * (-len(indices) % 4)
    fallback = {"byteLength": 32 * 4 + 12, "extensions": {"EXT_meshopt_compression": {"fallback": True}}}
    views = [{"buffer": 1, "byteOffset": 0, "byteLength": 128, "byteStride": 32, "extensions": {
        "EXT_meshopt_compression": {"buffer": 0, "byteOffset": compressed, "byteLength": len(packed),
                                    "byteStride": 32, "count": 4, "mode": "ATTRIBUTES"}}},
             {"buffer": 1, "byteOffset": 128, "byteLength": 12, "extensions": {
                 "EXT_meshopt_compression": {"buffer": 0, "byteOffset": index_at, "byteLength": len(indices),
                                             "byteStride": 2, "count": 6, "mode": "TRIANGLES"}}}]
    first_view = len(g.doc["bufferViews"])
    g.doc["bufferViews"] += views
    first = len(g.doc["accessors"])
    g.doc["accessors"] += [
        {"bufferView": first_view, "componentType": 5126, "count": 4, "type": "VEC3",
         "min": [-HALF, -HALF, 0], "max": [HALF, HALF, 0]},
        {"bufferView": first_view, "byteOffset": 12, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": first_view + 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]
    g.node(mesh=g.mesh([{"attributes": {"POSITION": first, "TEXCOORD_0": first + 1}, "indices": first + 2,
                         "material": mat}]))
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["EXT_meshopt_compression"]
    from gltf_gen import write_container

    doc = {**g.doc, "scene": 0, "scenes": [{"nodes": [0]}]}
    path = write_container(tmp_path / "meshopt.gltf", doc, bytes(g.data))
    import json

    written = json.loads(path.read_text())
    written["buffers"].append(fallback)  # the placeholder buffer the views name, with no data of its own
    path.write_text(json.dumps(written))
    return path


@pytest.mark.parametrize("which", PATHS)
def test_meshopt_compressed_quad(ctx, tmp_path, which):
    """EXT_meshopt_compression (data from meshoptimizer's encoder; the views point into a fallback buffer with no
    data): the quad's four texture quarters."""
    _meshopt_quad(tmp_path)
    quarters(render(ctx, write_scene(tmp_path, "meshopt.gltf"), which), which, "meshopt")


@pytest.mark.parametrize("module, make", [("DracoPy", _draco_quad), ("meshoptimizer", _meshopt_quad)])
def test_missing_decoder_is_one_line_naming_the_extension_and_pip(tmp_path, monkeypatch, module, make):
    path = make(tmp_path)
    monkeypatch.setitem(sys.modules, module, None)  # import now raises ImportError, as without the package
    with pytest.raises(UserError) as info:
        load_mesh(path)
    text = str(info.value)
    extension = {"DracoPy": "KHR_draco_mesh_compression", "meshoptimizer": "EXT_meshopt_compression"}[module]
    assert "\n" not in text and extension in text and f"pip install {module}" in text


def test_explain_lists_the_extensions_used(tmp_path, capsys):
    """--explain names each applied extension as used; each distinct (set, transform) of a material gets its own
    coordinate slot (the emissive and occlusion textures' slots 1 and 2), the normal texture's, equal to the base
    colour's, shares slot 0; nothing of the material is ignored."""
    from wgpurender.cli import main

    g = GltfWriter()
    tex = g.texture(TEXELS)
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex, "extensions": {
        "KHR_texture_transform": {"scale": [2, 2]}}}}, emissiveTexture={"index": tex}, emissiveFactor=[1, 1, 1],
        normalTexture={"index": tex, "extensions": {"KHR_texture_transform": {"scale": [2, 2]}}},
        occlusionTexture={"index": tex, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0]}}})
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-1, -1, 1, 1)),
                                        "TEXCOORD_0": g.accessor(QUAD_UV)}, "indices": g.accessor(QUAD_INDICES),
                         "material": mat}]))
    g.doc["extensionsUsed"] = ["KHR_texture_transform", "KHR_mesh_quantization", "KHR_materials_sheen"]
    g.write(tmp_path / "x.glb")
    assert main(["render", str(write_scene(tmp_path, "x.glb")), "--explain"]) == 0
    out = capsys.readouterr().out
    for line in ("extensionsUsed KHR_texture_transform: used", "extensionsUsed KHR_mesh_quantization: used",
                 "extensionsUsed KHR_materials_sheen: ignored",
                 "emissive_map_uv1", "occlusion_map_uv2", "TEXCOORD_0 with KHR_texture_transform {'offset': (0.5, 0)}"
                 ": coordinate slot 2"):
        assert line in out, line
    assert "normal_map_uv" not in out and "albedo_map_uv" not in out and "Texture: ignored" not in out


def test_a_gltf_scene_imports_neither_trimesh_nor_scipy(tmp_path):
    """Issue 30 item 5: rendering a glTF scene (both paths' loaders) never imports trimesh or scipy (1.84 s of a
    model scene's first pixel on the H100 host when it did)."""
    g = GltfWriter()
    textured_quad(g, {}, {"TEXCOORD_0": QUAD_UV})
    g.write(tmp_path / "m.glb")
    scene = write_scene(tmp_path, "m.glb")
    code = ("import sys\nfrom wgpurender.cli import main\n"
            f"assert main(['render', {str(scene)!r}, '-o', {str(tmp_path / 'a.png')!r}]) == 0\n"
            f"assert main(['reference', {str(scene)!r}, '-o', {str(tmp_path / 'b.png')!r}]) == 0\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('trimesh', 'scipy')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip().splitlines()[-1] == "[]"
    assert (tmp_path / "a.png").exists() and (tmp_path / "b.png").exists()


def test_one_morph_target_and_tangent_deltas(tmp_path):
    """A single target with weight 0.5 (the loader's arrays, no render): POSITION moves by half its delta, the
    TANGENT's xyz by half of its delta while w (handedness) stays the file's -1."""
    g = GltfWriter()
    base = quad(0, 0, 1, 1)
    tangents = np.tile(np.float32([1, 0, 0, -1]), (4, 1))
    delta_t = np.tile(np.float32([0, 2, 0]), (4, 1))
    prim = {"attributes": {"POSITION": g.positions(base), "TANGENT": g.accessor(tangents),
                           "NORMAL": g.accessor(np.tile(np.float32([0, 0, 1]), (4, 1)))},
            "indices": g.accessor(QUAD_INDICES),
            "targets": [{"POSITION": g.positions(np.tile(np.float32([0, 0, 0.8]), (4, 1))),
                         "TANGENT": g.accessor(delta_t)}]}
    g.node(mesh=g.mesh([prim]))
    g.doc["meshes"][0]["weights"] = [0.5]
    mesh = load_mesh(g.write(tmp_path / "one.glb"))
    assert np.allclose(mesh.positions[:, 2], 0.4)
    want = np.array([1, 1, 0]) / np.sqrt(2)  # (1, 0, 0) + 0.5 (0, 2, 0), normalised by the loader
    assert np.allclose(mesh.tangents[:, :3], want, atol=1e-6) and np.all(mesh.tangents[:, 3] == -1)


LINE_COLOUR, POINT_COLOUR, STRIP_COLOUR = (1.0, 0.2, 0.1), (0.1, 1.0, 0.3), (0.2, 0.4, 1.0)


def _modes_file(tmp_path):
    """MeshPrimitiveModes' point: a triangle quad at the bottom, then LINES (two horizontal segments), a
    LINE_LOOP (a square's outline), a LINE_STRIP (a vertical polyline) and POINTS, each its own unlit colour."""
    g = GltfWriter()
    mats = [g.material(pbrMetallicRoughness={"baseColorFactor": [*c, 1]}, **UNLIT)
            for c in ((0.5, 0.5, 0.5), LINE_COLOUR, POINT_COLOUR, STRIP_COLOUR)]
    quad_prim = {"attributes": {"POSITION": g.positions(quad(-1.6, -1.6, 1.6, -1.0))},
                 "indices": g.accessor(QUAD_INDICES), "material": mats[0]}
    lines = np.float32([[-1.5, 1.2, 0], [-0.3, 1.2, 0], [0.3, 1.2, 0], [1.5, 1.2, 0]])
    loop = np.float32([[-1.2, -0.6, 0], [-0.2, -0.6, 0], [-0.2, 0.4, 0], [-1.2, 0.4, 0]])
    strip = np.float32([[1.0, -0.7, 0], [1.0, 0.0, 0], [1.4, 0.0, 0], [1.4, 0.6, 0]])
    points = np.float32([[0.2, 0.2, 0], [0.5, -0.4, 0], [0.6, 0.7, 0]])
    prims = [quad_prim,
             {"attributes": {"POSITION": g.positions(lines)}, "mode": 1, "material": mats[1]},
             {"attributes": {"POSITION": g.positions(loop)}, "mode": 2, "material": mats[3]},
             {"attributes": {"POSITION": g.positions(strip)}, "mode": 3, "material": mats[3]},
             {"attributes": {"POSITION": g.positions(points)}, "mode": 0, "material": mats[2]}]
    g.node(mesh=g.mesh(prims))
    g.write(tmp_path / "modes.glb")
    return lines, loop, strip, points


def _near(image, x, y, colour, radius=1) -> bool:
    """Some pixel within ``radius`` of where the camera puts (x, y) shows ``colour`` (sRGB-encoded, within 3)."""
    from test_gltf_render import srgb_encode

    col, row = (int(v) for v in pixel_of(x, y, SIZE))
    patch = image[max(row - radius, 0): row + radius + 1, max(col - radius, 0): col + radius + 1, :3]
    return bool(np.any(np.abs(patch.astype(float) - srgb_encode(colour)).max(axis=2) <= 3))


@pytest.mark.parametrize("which", PATHS)
def test_points_and_lines_are_drawn(ctx, tmp_path, which):
    """Each segment's midpoint shows its primitive's colour, so does each point; the loop's closing segment
    (last vertex back to the first) is drawn; the gap between the two LINES segments, the strip's missing
    closing segment and the points' neighbourhood stay black; the quad still shows."""
    lines, loop, strip, points = _modes_file(tmp_path)
    image = render(ctx, write_scene(tmp_path, "modes.glb"), which)
    assert_colour(image, 0.0, -1.3, (0.5, 0.5, 0.5), f"{which} quad")
    for a, b, colour in ((lines[0], lines[1], LINE_COLOUR), (lines[2], lines[3], LINE_COLOUR),
                         *((loop[i], loop[(i + 1) % 4], STRIP_COLOUR) for i in range(4)),
                         *((strip[i], strip[i + 1], STRIP_COLOUR) for i in range(3))):
        mid = (a + b) / 2
        assert _near(image, mid[0], mid[1], colour), (which, a.tolist(), b.tolist())
    for p in points:
        assert _near(image, p[0], p[1], POINT_COLOUR), (which, p.tolist())
        col, row = (int(v) for v in pixel_of(p[0], p[1], SIZE))
        assert image[row - 3: row + 4, col - 3: col + 4, :3].max(axis=2).astype(bool).sum() <= 4  # 1-pixel points
    black = [(0.0, 1.2), ((strip[0][0] + strip[3][0]) / 2, (strip[0][1] + strip[3][1]) / 2)]
    for x, y in black:
        col, row = (int(v) for v in pixel_of(x, y, SIZE))
        assert image[row, col, :3].max() == 0, (which, x, y)


def test_explain_says_points_and_lines_are_drawn_unlit(tmp_path, capsys):
    from wgpurender.cli import main

    _modes_file(tmp_path)
    assert main(["render", str(write_scene(tmp_path, "modes.glb")), "--explain"]) == 0
    out = capsys.readouterr().out
    assert "POINTS primitive drawn unlit as a point-list" in out and "LINE_LOOP primitive drawn unlit" in out
    assert "| line-list" in out and "| point-list" in out  # their own pipelines


def test_meshopt_views_that_claim_too_much_are_refused_before_decoding(tmp_path):
    """A compressed view's count x byteStride is what the decoder allocates: 2^40 vertices of a 32-byte stride
    (32 TiB from a few bytes) is refused in one line, before any allocation."""
    import json

    path = _meshopt_quad(tmp_path)
    doc = json.loads(path.read_text())
    doc["bufferViews"][-2]["extensions"]["EXT_meshopt_compression"]["count"] = 2**40
    path.write_text(json.dumps(doc))
    with pytest.raises(UserError, match="EXT_meshopt_compression views decode to .* over the model limit"):
        load_mesh(path)


def test_instances_beyond_the_model_limit_are_refused(tmp_path, monkeypatch):
    """EXT_mesh_gpu_instancing multiplies vertices: 4 instances of a 4-vertex quad under a budget of 10 placed
    vertices ($WGPURENDER_MAX_MODEL_VERTICES) is one line, not an allocation that grows with the instance count;
    under 24 they fit (without NORMAL each quad is flat-shaded: 6 vertices, glTF 2.0 3.7.2.1)."""
    g = GltfWriter()
    mesh = g.mesh([{"attributes": {"POSITION": g.positions(quad(-0.3, -0.3, 0.3, 0.3))},
                    "indices": g.accessor(QUAD_INDICES)}])
    g.node(mesh=mesh, extensions={"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": g.accessor(
        INSTANCES_T)}}})
    path = g.write(tmp_path / "many.glb")
    monkeypatch.setattr("wgpurender.core.models.gltf_geometry.env_limit", lambda name, default: 10)
    with pytest.raises(UserError, match="place over 10 vertices"):
        load_mesh(path)
    monkeypatch.setattr("wgpurender.core.models.gltf_geometry.env_limit", lambda name, default: 24)
    assert load_mesh(path, generate_tangents=False).vertex_count == 24


def test_draco_with_an_uncompressed_fallback_loads_without_dracopy(tmp_path, monkeypatch):
    """KHR_draco_mesh_compression only in extensionsUsed, the accessors also pointing at plain data: without
    DracoPy the fallback is read (with it, the Draco data)."""
    import importlib.util
    import json

    from gltf_gen import write_container

    path = _draco_quad(tmp_path)
    raw = path.read_bytes()  # the GLB's JSON and BIN chunks, edited to add plain copies of the data
    (json_len,) = np.frombuffer(raw[12:16], "<u4")
    doc = json.loads(raw[20:20 + json_len])
    binary = raw[20 + json_len + 8:]
    fallback = quad(-0.5, -0.5, 0.5, 0.5)  # a smaller quad: which data was read shows in the positions
    offset = len(binary)
    binary += fallback.tobytes()
    doc["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": fallback.nbytes})
    position = doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
    doc["accessors"][position]["bufferView"] = len(doc["bufferViews"]) - 1
    doc["accessors"][position].update(min=[-0.5, -0.5, 0], max=[0.5, 0.5, 0])
    uv = doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"]
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": QUAD_UV.nbytes})
    binary += QUAD_UV.tobytes()
    doc["accessors"][uv]["bufferView"] = len(doc["bufferViews"]) - 1
    indices = doc["meshes"][0]["primitives"][0]["indices"]
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": QUAD_INDICES.nbytes})
    binary += QUAD_INDICES.tobytes()
    doc["accessors"][indices]["bufferView"] = len(doc["bufferViews"]) - 1
    doc["extensionsRequired"] = []
    write_container(path, {k: v for k, v in doc.items() if k != "buffers"}, binary)
    with_draco = load_mesh(path, generate_tangents=False)
    assert np.allclose(np.abs(with_draco.positions[:, :2]).max(), HALF, atol=1e-3)
    real_find_spec = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "DracoPy" else
                        real_find_spec(name, *a))
    without = load_mesh(path, generate_tangents=False)
    assert np.allclose(np.abs(without.positions[:, :2]).max(), 0.5)


def test_meshopt_octahedral_filter_decodes_normals(tmp_path):
    """EXT_meshopt_compression's OCTAHEDRAL filter on int16 normals (KHR_mesh_quantization's normalized SHORT):
    the encoded (x, y, z) = (16383, 0, 32767) means oct (0.5, 0) with z = 1 - |x| - |y| = 0.5, i.e. the unit
    normal (1, 0, 1) / sqrt(2) (the filter's definition in the extension's text)."""
    import json

    meshopt = pytest.importorskip("meshoptimizer")
    from gltf_gen import write_container

    positions = quad(-1, -1, 1, 1)
    encoded_normals = np.tile(np.int16([16383, 0, 32767, 0]), (4, 1))
    data = bytearray()
    views, accessors = [], []
    for array, stride, extra in ((positions, 12, {}), (encoded_normals, 8, {"filter": "OCTAHEDRAL"})):
        packed = bytes(meshopt.encode_vertex_buffer(np.ascontiguousarray(array), 4, stride))
        views.append({"buffer": 1, "byteOffset": 0, "byteLength": 4 * stride, "byteStride": stride, "extensions": {
            "EXT_meshopt_compression": {"buffer": 0, "byteOffset": len(data), "byteLength": len(packed),
                                        "byteStride": stride, "count": 4, "mode": "ATTRIBUTES", **extra}}})
        data += packed + b"\0" * (-len(packed) % 4)
    views.append({"buffer": 0, "byteOffset": len(data), "byteLength": QUAD_INDICES.nbytes})
    data += QUAD_INDICES.tobytes()
    accessors = [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0],
                  "max": [1, 1, 0]},
                 {"bufferView": 1, "componentType": 5122, "normalized": True, "count": 4, "type": "VEC3"},
                 {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
           "bufferViews": views, "accessors": accessors,
           "extensionsUsed": ["EXT_meshopt_compression", "KHR_mesh_quantization"]}
    path = write_container(tmp_path / "oct.gltf", doc, bytes(data))
    written = json.loads(path.read_text())
    written["buffers"].append({"byteLength": 4 * 20, "extensions": {"EXT_meshopt_compression": {"fallback": True}}})
    path.write_text(json.dumps(written))
    mesh = load_mesh(path, generate_tangents=False)
    np.testing.assert_allclose(mesh.normals, np.tile([1 / np.sqrt(2), 0, 1 / np.sqrt(2)], (4, 1)), atol=1e-3)
    np.testing.assert_allclose(mesh.positions, positions)


def _write_transform(tmp_path):
    g = GltfWriter()
    textured_quad(g, {"extensions": {"KHR_texture_transform": TRANSFORMS["all"]}}, {"TEXCOORD_0": QUAD_UV})
    g.write(tmp_path / "tt.glb")
    return "tt.glb"


def _write_instances(tmp_path):
    g = GltfWriter()
    mesh = g.mesh([{"attributes": {"POSITION": g.positions(quad(-0.3, -0.3, 0.3, 0.3))},
                    "indices": g.accessor(QUAD_INDICES)}])
    attrs = {"TRANSLATION": g.accessor(INSTANCES_T), "SCALE": g.accessor(INSTANCES_S),
             "ROTATION": g.accessor(INSTANCES_R)}
    g.node(mesh=mesh, extensions={"EXT_mesh_gpu_instancing": {"attributes": attrs}})
    g.write(tmp_path / "inst.glb")
    return "inst.glb"


def _write_modes(tmp_path):
    _modes_file(tmp_path)
    return "modes.glb"


def _write_draco(tmp_path):
    _draco_quad(tmp_path)
    return "draco.glb"


@pytest.mark.parametrize("make", [_write_transform, _write_instances, _write_modes, _write_draco],
                         ids=["texture_transform", "instancing", "points_lines", "draco"])
def test_wgpu_equals_raw_within_one_run(ctx, tmp_path, make):
    """The two paths draw the same file to the same bytes on this machine in this run (lavapipe, same rasterizer):
    the extensions are applied once, in the core, and each path's pipeline takes the same topology."""
    scene = write_scene(tmp_path, make(tmp_path))
    wgpu_image, raw_image = render(ctx, scene, "wgpu"), render(ctx, scene, "raw")
    assert wgpu_image[..., :3].max() > 0
    np.testing.assert_array_equal(wgpu_image, raw_image)


def test_a_draco_primitive_is_decoded_once_per_document_and_handed_out_fresh(tmp_path, monkeypatch):
    """The window re-poses an animated model from the same parsed document every frame: its Draco primitive is
    decoded once for that document (a document read again decodes again), each call gets arrays of its own (a
    caller changing them changes no later call), equal to the first decode's."""
    DracoPy = pytest.importorskip("DracoPy")
    from wgpurender.core.models import gltf_compression, gltf_io

    path = _draco_quad(tmp_path)
    decodes = []
    real = DracoPy.decode
    monkeypatch.setattr(DracoPy, "decode", lambda data: decodes.append(len(data)) or real(data))
    doc = gltf_io.read_document(path)
    prim = doc.json["meshes"][0]["primitives"][0]
    first, faces = gltf_compression.draco_attributes(doc, prim, "mesh 0")
    first["POSITION"][:] = 99.0
    faces[:] = 0
    again, faces_again = gltf_compression.draco_attributes(doc, prim, "mesh 0")
    assert len(decodes) == 1
    assert np.abs(again["POSITION"][:, :2]).max() == pytest.approx(HALF, abs=1e-3)  # not the 99 written above
    assert faces_again.max() == 3 and len(faces_again) == 2  # the quad's two triangles over its four corners
    other = gltf_io.read_document(path)
    gltf_compression.draco_attributes(other, other.json["meshes"][0]["primitives"][0], "mesh 0")
    assert len(decodes) == 2
