"""The glTF loader reads every attribute itself (wgpurender/core/models/gltf_geometry.py, gltf_io.read_accessor).

Each file is generated here (tests/gltf_gen.py); each expectation comes from the arrays written into it: sparse
accessors, normalized integer types, interleaved views (byteStride), strips and fans, the node hierarchy, COLOR_0,
per-material index ranges, and the refusals (glTF 1.0, unknown required extensions, cycles).
"""

from __future__ import annotations

import json
import math
import struct

import numpy as np
import pytest
from gltf_gen import QUAD_INDICES, GltfWriter, quad

from wgpurender.core.errors import UserError
from wgpurender.core.models.mesh import load_mesh

STRIP_TOP = np.array([2.0, 3.0, 4.0], np.float32)  # the heights the sparse block lifts the top vertices to


def up(g: GltfWriter) -> int:
    """A NORMAL accessor (+z) for a quad: with normals given, a mesh keeps the file's vertices (without, glTF asks
    for flat normals, which split every vertex per triangle)."""
    return g.accessor(np.tile(np.float32([0, 0, 1]), (4, 1)))


def _strip_file(tmp_path, suffix=".glb"):
    """A strip of 3 quads along x (8 vertices: bottom row y = 0, top row y = 1), then a sparse block that
    replaces top vertices 5, 6, 7 with heights STRIP_TOP. Returns (path, the positions the file means)."""
    base = np.array([[x, 0, 0] for x in range(4)] + [[x, 1, 0] for x in range(4)], np.float32)
    changed = np.array([5, 6, 7], np.uint16)
    values = base[changed].copy()
    values[:, 1] = STRIP_TOP
    g = GltfWriter()
    pos = g.positions(base, sparse=(changed, values))
    faces = np.array([[k, k + 1, k + 5, k, k + 5, k + 4] for k in range(3)], np.uint16).ravel()
    up = g.accessor(np.tile(np.float32([0, 0, 1]), (8, 1)))  # given normals: vertices stay as the file has them
    g.node(mesh=g.mesh([{"attributes": {"POSITION": pos, "NORMAL": up}, "indices": g.accessor(faces)}]))
    want = base.copy()
    want[changed] = values  # what the file means: glTF 2.0 section 3.6.2.3
    return g.write(tmp_path / f"strip{suffix}"), want


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_sparse_positions_are_applied(tmp_path, suffix):
    path, want = _strip_file(tmp_path, suffix)
    mesh = load_mesh(path)
    np.testing.assert_array_equal(mesh.positions, want)
    assert sorted(mesh.positions[:, 1].tolist())[-3:] == STRIP_TOP.tolist()


def test_sparse_accessor_without_a_buffer_view_starts_from_zeros(tmp_path):
    """An accessor with no bufferView is all zeros; its sparse block then sets some elements (here the UVs)."""
    g = GltfWriter()
    uv_values = np.array([[0.25, 0.75], [0.5, 0.125]], np.float32)
    uv = g.accessor(None, count=4, width=2, sparse=(np.array([1, 3], np.uint8), uv_values))
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(0, 0, 1, 1)), "TEXCOORD_0": uv, "NORMAL": up(g)},
                         "indices": g.accessor(QUAD_INDICES)}]))
    mesh = load_mesh(g.write(tmp_path / "zeros.gltf"))
    want = np.zeros((4, 2), np.float32)
    want[[1, 3]] = uv_values
    np.testing.assert_array_equal(mesh.uvs, want)


def test_normalized_integer_colours_and_uvs(tmp_path):
    """COLOR_0 as normalized unsigned bytes (x / 255) with 3 components (alpha 1), TEXCOORD_0 as normalized
    unsigned shorts (x / 65535)."""
    colors = np.array([[255, 0, 0], [0, 128, 0], [0, 0, 255], [10, 20, 30]], np.uint8)
    uvs = np.array([[0, 65535], [65535, 65535], [65535, 0], [32768, 1]], np.uint16)
    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(0, 0, 1, 1)), "NORMAL": up(g),
                                        "COLOR_0": g.accessor(colors, normalized=True),
                                        "TEXCOORD_0": g.accessor(uvs, normalized=True)},
                         "indices": g.accessor(QUAD_INDICES)}]))
    mesh = load_mesh(g.write(tmp_path / "norm.glb"))
    np.testing.assert_allclose(mesh.colors, np.c_[colors / 255.0, np.ones(4)], atol=1e-7)
    np.testing.assert_allclose(mesh.uvs, uvs / 65535.0, atol=1e-7)


def test_interleaved_view_with_byte_stride(tmp_path):
    """Position (12 bytes), normal (12) and colour (4 normalized bytes) interleaved in one view, stride 28."""
    pos = quad(0, 0, 1, 1)
    normals = np.tile(np.float32([0, 0.6, 0.8]), (4, 1))
    colors = np.array([[255, 0, 0, 255], [0, 255, 0, 128], [0, 0, 255, 0], [51, 102, 153, 204]], np.uint8)
    raw = b"".join(p.tobytes() + n.tobytes() + c.tobytes() for p, n, c in zip(pos, normals, colors, strict=True))
    g = GltfWriter()
    view = g.view(raw, stride=28)
    attrs = {"POSITION": g.accessor(pos, view=view), "NORMAL": g.accessor(normals, view=view, offset=12),
             "COLOR_0": g.accessor(colors, view=view, offset=24, normalized=True)}
    g.doc["accessors"][attrs["POSITION"]].update(min=[0, 0, 0], max=[1, 1, 0])
    g.node(mesh=g.mesh([{"attributes": attrs, "indices": g.accessor(QUAD_INDICES)}]))
    mesh = load_mesh(g.write(tmp_path / "interleaved.glb"))
    np.testing.assert_array_equal(mesh.positions, pos)
    np.testing.assert_allclose(mesh.normals, normals, atol=1e-6)
    np.testing.assert_allclose(mesh.colors, colors / 255.0, atol=1e-7)


@pytest.mark.parametrize("mode", [5, 6])
def test_strips_and_fans_become_counter_clockwise_triangles(tmp_path, mode):
    """A TRIANGLE_STRIP (mode 5) or TRIANGLE_FAN (mode 6) quad without indices: 2 triangles, both facing +z."""
    pos = {5: np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]),
           6: quad(0, 0, 1, 1)}[mode]
    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(pos)}, "mode": mode}]))
    mesh = load_mesh(g.write(tmp_path / "strip.gltf"), generate_tangents=False)
    assert mesh.triangle_count == 2
    p = mesh.positions[mesh.indices.astype(int)]
    normals = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    np.testing.assert_allclose(normals, [[0, 0, 1], [0, 0, 1]], atol=1e-6)


def test_node_hierarchy_composes_parent_and_child(tmp_path):
    """Parent: translation (10, 0, 0); child: rotation 90 degrees about z, scale 2. A vertex (1, 0, 0) lands at
    (10, 2, 0): parent @ child, T @ R @ S, written here with the quaternion's own formula."""
    g = GltfWriter()
    mesh = g.mesh([{"attributes": {"POSITION": g.positions(quad(0, 0, 1, 1)), "NORMAL": up(g)},
                    "indices": g.accessor(QUAD_INDICES)}])
    s = math.sin(math.pi / 4)
    child = g.node(mesh=mesh, rotation=[0, 0, s, s], scale=[2, 2, 2])
    parent = g.node(children=[child], translation=[10, 0, 0])
    loaded = load_mesh(g.write(tmp_path / "tree.gltf", roots=[parent]))
    # rotating (x, y) by 90 degrees gives (-y, x); then scale 2, then + (10, 0, 0)
    want = np.c_[10 - 2 * quad(0, 0, 1, 1)[:, 1], 2 * quad(0, 0, 1, 1)[:, 0], np.zeros(4)]
    np.testing.assert_allclose(loaded.positions, want, atol=1e-5)


def test_primitives_are_grouped_by_material(tmp_path):
    """Three primitives with materials 1, 0, 1: the mesh keeps each material's triangles together."""
    g = GltfWriter()
    g.material(name="a")
    g.material(name="b")
    prims = [{"attributes": {"POSITION": g.positions(quad(x, 0, x + 1, 1))}, "indices": g.accessor(QUAD_INDICES),
              "material": m} for x, m in ((0, 1), (2, 0), (4, 1))]
    g.node(mesh=g.mesh(prims))
    mesh = load_mesh(g.write(tmp_path / "mats.glb"), generate_tangents=False)
    assert [(p.material, p.first_index, p.index_count) for p in mesh.parts] == [(0, 0, 6), (1, 6, 12)]
    xs = mesh.positions[mesh.indices.ravel().astype(int), 0]
    assert xs[:6].min() >= 2 and xs[:6].max() <= 3  # material 0 is the quad at x = 2..3


def _error(path) -> str:
    with pytest.raises(UserError) as info:
        load_mesh(path)
    return str(info.value)


def test_gltf_1_is_refused_with_its_version(tmp_path):
    doc = {"asset": {"version": "1.0"}, "scene": "defaultScene", "scenes": {"defaultScene": {"nodes": []}}}
    (tmp_path / "old.gltf").write_text(json.dumps(doc))
    message = _error(tmp_path / "old.gltf")
    assert "glTF 1.0 is not supported" in message and "2.0" in message
    text = json.dumps({"asset": {"version": "1.0"}}).encode()
    body = struct.pack("<II", len(text), 0) + text
    (tmp_path / "old.glb").write_bytes(struct.pack("<III", 0x46546C67, 1, 12 + len(body)) + body)
    assert "binary glTF version 1 is not supported" in _error(tmp_path / "old.glb")


def test_unknown_required_extension_is_refused_by_name(tmp_path):
    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(0, 0, 1, 1))}}]))
    g.doc["extensionsRequired"] = ["KHR_texture_basisu"]
    g.doc["extensionsUsed"] = ["KHR_texture_basisu"]
    message = _error(g.write(tmp_path / "basisu.gltf"))
    assert "KHR_texture_basisu" in message and "not support" in message


def test_a_children_cycle_is_refused(tmp_path):
    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(0, 0, 1, 1))}}]), children=[1])
    g.node(children=[0])
    assert "cycle" in _error(g.write(tmp_path / "cycle.gltf", roots=[0]))


def test_sparse_indices_out_of_range_are_refused(tmp_path):
    g = GltfWriter()
    pos = g.positions(quad(0, 0, 1, 1), sparse=(np.array([9], np.uint16), np.float32([[0, 5, 0]])))
    g.node(mesh=g.mesh([{"attributes": {"POSITION": pos}}]))
    assert "sparse" in _error(g.write(tmp_path / "bad.gltf"))


def test_unnormalized_integer_attributes_are_refused(tmp_path):
    """Integer TEXCOORD without normalized: true is KHR_mesh_quantization's form, refused with one line."""
    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(0, 0, 1, 1)),
                                        "TEXCOORD_0": g.accessor(np.zeros((4, 2), np.uint16))},
                         "indices": g.accessor(QUAD_INDICES)}]))
    message = _error(g.write(tmp_path / "quantized.glb"))
    assert "TEXCOORD_0" in message and "KHR_mesh_quantization" in message


def test_mtl_colour_opacity_and_illum_are_read(tmp_path):
    """Kd (a single value is grey), d and Tr, illum; a Kd that is not a number is refused with FILE:LINE."""
    from wgpurender.core.scene.file_materials import parse_mtl

    (tmp_path / "m.mtl").write_text("newmtl a\nKd 0.5 0.25 1\nd 0.4\nillum 0\nnewmtl b\nKd 0.3\nTr 0.25\n")
    found = parse_mtl(tmp_path / "m.mtl")
    assert found["a"].color == (0.5, 0.25, 1.0) and found["a"].opacity == 0.4 and found["a"].illum == 0
    assert found["b"].color == (0.3, 0.3, 0.3) and found["b"].opacity == 0.75 and found["b"].illum is None
    (tmp_path / "bad.mtl").write_text("newmtl a\nKd red\n")
    with pytest.raises(UserError, match=r"bad.mtl:2: Kd needs numbers"):
        parse_mtl(tmp_path / "bad.mtl")
