"""Mesh loading (core/models/mesh.py): formats, the UV convention, indices, normals, errors, a 1M-triangle load.

The UV convention (v = 0 at the TOP of the image) is proven against values written by hand into each file:
glTF's TEXCOORD_0 must come back exactly (float32 equality), OBJ/PLY's v must come back as 1 - v (1e-7).
Normals are compared with analytic ones (1e-6 for exact cases, 1 degree on an icosphere), transforms with numpy
float64 matrices (1e-6).
"""

from __future__ import annotations

import base64
import importlib.util
import json
import struct
from pathlib import Path

import numpy as np
import pytest
import trimesh
from gltf_gen import write_container

from wgpurender.core.errors import UserError
from wgpurender.core.models import procedural as proc
from wgpurender.core.models.mesh import build_mesh, index_dtype, load_mesh
from wgpurender.core.models.tangents import area_weighted_normals
from wgpurender.core.scene.file_materials import obj_mtl_entry, parse_mtl

ROOT = Path(__file__).resolve().parent.parent
QUAD_POS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
QUAD_IDX = np.array([0, 1, 2, 0, 2, 3], np.uint16)
# deliberately asymmetric values so any flip or swap shows; glTF convention (v = 0 at the top)
QUAD_UV = np.array([[0.1, 0.8], [0.9, 0.85], [0.8, 0.05], [0.05, 0.3]], np.float32)
UP = np.tile(np.float32([0, 0, 1]), (4, 1))  # given normals: the loader keeps the file's vertices (no flat split)


def write_gltf(path: Path, attributes: dict, indices: np.ndarray, *, material: bool = False, nodes=None) -> Path:
    """A glTF written by hand: JSON plus one buffer (base64 data URI for .gltf, BIN chunk for .glb).

    Independent of wgpurender.core.models.gltf_io, so the loader is checked against the file format, not against itself.
    """
    names = list(attributes)
    blobs = [np.asarray(attributes[n], np.float32) for n in names] + [np.asarray(indices, np.uint16)]
    data, views, accessors = b"", [], []
    for k, blob in enumerate(blobs):
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": blob.nbytes})
        data += blob.tobytes() + b"\0" * (-blob.nbytes % 4)
        accessors.append({"bufferView": k, "componentType": 5123 if blob.dtype == np.uint16 else 5126,
                          "count": len(blob), "type": "SCALAR" if blob.ndim == 1 else f"VEC{blob.shape[1]}"})
    p = names.index("POSITION")
    accessors[p].update(min=blobs[p].min(0).tolist(), max=blobs[p].max(0).tolist())
    prim = {"attributes": {n: i for i, n in enumerate(names)}, "indices": len(names)}
    doc = {"asset": {"version": "2.0"}, "scene": 0, "meshes": [{"primitives": [prim]}],
           "bufferViews": views, "accessors": accessors}
    doc["nodes"] = nodes or [{"mesh": 0}]
    doc["scenes"] = [{"nodes": list(range(len(doc["nodes"])))}]
    if material:
        prim["material"] = 0
        doc.update(materials=[{"name": "m", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
                               "normalTexture": {"index": 1}}],
                   textures=[{"source": 0}, {"source": 1}],
                   images=[{"uri": "albedo.png"}, {"uri": "normal.png"}])
    return write_container(path, doc, data)


# ------------------------------------------------------------------ UV convention


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
@pytest.mark.parametrize("material", [False, True])
def test_gltf_uvs_come_back_exactly_as_the_file_stores_them(tmp_path, suffix, material):
    """glTF stores v = 0 at the top, our convention: loaded uvs equal the file's TEXCOORD_0 bit for bit, with or
    without a material. trimesh alone flips v (1 - v) when there is a material and drops the uvs when there is
    none; asserting that here shows what the loader undoes (and fails loudly should trimesh change)."""
    path = write_gltf(tmp_path / f"quad{suffix}", {"POSITION": QUAD_POS, "NORMAL": UP, "TEXCOORD_0": QUAD_UV},
                      QUAD_IDX, material=material)
    mesh = load_mesh(path)
    assert mesh.has_uvs
    np.testing.assert_array_equal(mesh.uvs, QUAD_UV)
    np.testing.assert_array_equal(mesh.positions, QUAD_POS)
    np.testing.assert_array_equal(mesh.indices.ravel(), QUAD_IDX)

    geom = next(iter(trimesh.load_scene(str(path), process=False).geometry.values()))
    if material:
        np.testing.assert_allclose(geom.visual.uv, np.c_[QUAD_UV[:, 0], 1 - QUAD_UV[:, 1]], atol=1e-7)
    else:
        assert getattr(geom.visual, "uv", None) is None


def write_quad_obj(tmp_path: Path) -> Path:
    """The quad of QUAD_UV authored as OBJ: vt stores 1 - v (OBJ: v = 0 at the bottom). Vertex 1 is used with two
    different vt (corner split), the normal is tilted on purpose (file normals must be kept, not recomputed)."""
    vt = [f"vt {u:.7f} {1 - v:.7f}" for u, v in QUAD_UV] + ["vt 0.5 0.5"]
    (tmp_path / "quad.mtl").write_text(
        "newmtl brick\nKd 1 1 1\nmap_Kd textures/albedo.png\nmap_Bump -bm 0.5 textures/normal.png\n"
        "map_Pr rough.png\nnewmtl other\nmap_Kd other.png\n")
    (tmp_path / "quad.obj").write_text("\n".join([
        "mtllib quad.mtl", *[f"v {x} {y} {z}" for x, y, z in QUAD_POS], *vt, "vn 0 0.6 0.8", "usemtl brick",
        "f 1/1/1 2/2/1 3/3/1", "f 1/1/1 3/3/1 4/4/1", "f 2/5/1 3/3/1 4/4/1",
    ]) + "\n")
    return tmp_path / "quad.obj"


def test_obj_v_is_converted_and_per_corner_attributes_survive(tmp_path):
    """OBJ vt (u, 1 - v) loads as (u, v); vertex 2 appears with vt 2 and vt 5, so it must be split into two
    vertices (5 in all) with their own uvs; the file's (tilted) normal is kept; MTL maps resolve to paths."""
    mesh = load_mesh(write_quad_obj(tmp_path))
    assert mesh.vertex_count == 5 and mesh.triangle_count == 3
    corner_uv = mesh.uvs[mesh.indices.ravel()]
    want = np.concatenate([QUAD_UV[[0, 1, 2]], QUAD_UV[[0, 2, 3]], [[0.5, 0.5]], QUAD_UV[[2, 3]]])
    np.testing.assert_allclose(corner_uv, want, atol=1e-7)
    np.testing.assert_allclose(mesh.positions[mesh.indices.ravel()],
                               QUAD_POS[[0, 1, 2, 0, 2, 3, 1, 2, 3]], atol=1e-7)
    np.testing.assert_allclose(mesh.normals, np.tile([0, 0.6, 0.8], (5, 1)), atol=1e-6)
    entry = obj_mtl_entry(tmp_path / "quad.obj")  # the scene's reader of the OBJ's material (its first usemtl)
    assert entry.name == "brick"
    assert entry.textures == {"base_color": (tmp_path / "textures/albedo.png").resolve(),
                              "normal": (tmp_path / "textures/normal.png").resolve(),
                              "roughness": (tmp_path / "rough.png").resolve()}
    assert set(parse_mtl(tmp_path / "quad.mtl")) == {"brick", "other"}


def test_obj_and_gltf_of_the_same_quad_load_identically(tmp_path):
    """Same surface, each format in its own V convention: after loading, uvs agree (1e-7) per corner."""
    gl = load_mesh(write_gltf(tmp_path / "q.gltf", {"POSITION": QUAD_POS, "NORMAL": UP, "TEXCOORD_0": QUAD_UV},
                              QUAD_IDX))
    (tmp_path / "q.obj").write_text("\n".join([*[f"v {x} {y} {z}" for x, y, z in QUAD_POS],
                                               *[f"vt {u:.7f} {1 - v:.7f}" for u, v in QUAD_UV],
                                               "f 1/1 2/2 3/3", "f 1/1 3/3 4/4"]) + "\n")
    ob = load_mesh(tmp_path / "q.obj")
    np.testing.assert_allclose(ob.uvs[ob.indices.ravel()], gl.uvs[gl.indices.ravel()], atol=1e-7)
    np.testing.assert_allclose(ob.tangents[ob.indices.ravel()], gl.tangents[gl.indices.ravel()], atol=1e-6)


def test_ply_with_normals_and_uvs(tmp_path):
    """ASCII PLY with nx ny nz and s t: normals kept as written, t = 1 - v converted to our v."""
    rows = [f"{x} {y} {z} 0 0 1 {u:.7f} {1 - v:.7f}" for (x, y, z), (u, v) in zip(QUAD_POS, QUAD_UV, strict=True)]
    props = [f"property float {p}" for p in "x y z nx ny nz s t".split()]
    header = ["ply", "format ascii 1.0", "element vertex 4", *props, "element face 2",
              "property list uchar int vertex_indices", "end_header"]
    (tmp_path / "q.ply").write_text("\n".join(header + rows + ["3 0 1 2", "3 0 2 3"]) + "\n")
    mesh = load_mesh(tmp_path / "q.ply")
    np.testing.assert_allclose(mesh.uvs, QUAD_UV, atol=1e-7)
    np.testing.assert_allclose(mesh.normals, np.tile([0, 0, 1], (4, 1)))
    assert mesh.has_uvs


def test_stl_has_flat_normals_and_no_uvs(tmp_path):
    """Binary STL, two triangles with different facing: 3 vertices per triangle (STL shares nothing), each with its
    face's unit normal; no uvs (zeros, has_uvs False); tangents still unit and orthogonal to the normals."""
    tris = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 0, 0], [0, 0, 1], [1, 0, 0]]], np.float32)
    rec = np.zeros(2, [("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    rec["v"] = tris
    (tmp_path / "t.stl").write_bytes(b"\0" * 80 + struct.pack("<I", 2) + rec.tobytes())
    mesh = load_mesh(tmp_path / "t.stl")
    assert mesh.vertex_count == 6 and not mesh.has_uvs
    np.testing.assert_array_equal(mesh.uvs, 0)
    np.testing.assert_allclose(mesh.normals, [[0, 0, 1]] * 3 + [[0, 1, 0]] * 3, atol=1e-7)
    assert np.abs(np.einsum("ij,ij->i", mesh.tangents[:, :3], mesh.normals)).max() < 1e-6


# ------------------------------------------------------------------ glTF tangents, transforms


def test_gltf_without_tangent_generates_them(tmp_path):
    """No TANGENT: tangents are generated. The uvs are an affine map uv = A (x, y) + c of the quad, so dP/du is the
    first column of A^-1 on both triangles: t must be its direction (1e-6), w = +1 (det A < 0 is unmirrored with v
    growing downwards). generate_tangents=False leaves None."""
    a = np.array([[0.6, 0.2], [-0.1, -0.7]])
    uv = (QUAD_POS[:, :2] @ a.T + [0.2, 0.9]).astype(np.float32)
    path = write_gltf(tmp_path / "q.glb", {"POSITION": QUAD_POS, "NORMAL": np.tile([0, 0, 1], (4, 1)),
                                           "TEXCOORD_0": uv}, QUAD_IDX)
    mesh = load_mesh(path)
    assert mesh.tangents_source == "generated"
    du = np.linalg.inv(a)[:, 0]
    want = np.r_[du / np.linalg.norm(du), 0.0, 1.0]
    np.testing.assert_allclose(mesh.tangents, np.tile(want, (4, 1)), atol=1e-6)
    assert load_mesh(path, generate_tangents=False).tangents is None


def test_gltf_node_transform_applies_to_positions_normals_tangents(tmp_path):
    """Node matrix = translate(1,2,3) @ rotate_z(90 deg) @ scale(-1, 1, 1) (mirrors). Expected, in float64 numpy:
    positions M p, normals by the inverse transpose (outward), tangent xyz by the 3x3 with w negated, and triangle
    winding reversed so it still agrees with the normals."""
    tangents = np.tile(np.float32([1, 0, 0, 1]), (4, 1))
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    rz = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]], float)
    m3 = rz @ np.diag([-1.0, 1, 1])
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = m3, [1, 2, 3]
    path = write_gltf(tmp_path / "n.gltf", {"POSITION": QUAD_POS, "NORMAL": normals, "TEXCOORD_0": QUAD_UV,
                                            "TANGENT": tangents}, QUAD_IDX,
                      nodes=[{"mesh": 0, "matrix": matrix.T.ravel().tolist()}])  # glTF matrices are column-major
    mesh = load_mesh(path)
    np.testing.assert_allclose(mesh.positions, QUAD_POS @ m3.T + [1, 2, 3], atol=1e-6)
    want_n = normals @ np.linalg.inv(m3)  # (M^-T n)^T = n^T M^-1
    np.testing.assert_allclose(mesh.normals, want_n / np.linalg.norm(want_n, axis=1, keepdims=True), atol=1e-6)
    np.testing.assert_allclose(mesh.tangents[:, :3], tangents[:, :3] @ m3.T, atol=1e-6)
    np.testing.assert_array_equal(mesh.tangents[:, 3], -1.0)
    p = mesh.positions[mesh.indices.astype(int)].astype(float)
    face_n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    assert np.all(np.einsum("ij,ij->i", face_n, mesh.normals[mesh.indices[:, 0]]) > 0)


def test_gltf_several_meshes_primitives_and_instances(tmp_path):
    """Mesh "a" = a triangle primitive + a POINTS primitive (its 4 vertices come after the triangles', drawn as a
    point list), mesh "b" = one triangle primitive placed by two nodes (translated by +10 and +20 in x). Each placed
    part must keep its own file uvs (a: QUAD_UV, b: QUAD_UV / 2): 4 + 4 + 4 triangle vertices, positions offset
    per node."""
    data, views, accessors = b"", [], []

    def add(array, component=5126):
        nonlocal data
        array = np.ascontiguousarray(array, np.uint16 if component == 5123 else np.float32)
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": array.nbytes})
        data += array.tobytes() + b"\0" * (-array.nbytes % 4)
        kind = "SCALAR" if array.ndim == 1 else f"VEC{array.shape[1]}"
        accessors.append({"bufferView": len(views) - 1, "componentType": component, "count": len(array), "type": kind})
        if kind == "VEC3":
            accessors[-1].update(min=array.min(0).tolist(), max=array.max(0).tolist())
        return len(accessors) - 1

    pos, idx, up = add(QUAD_POS), add(QUAD_IDX, 5123), add(UP)
    tri_a = {"attributes": {"POSITION": pos, "NORMAL": up, "TEXCOORD_0": add(QUAD_UV)}, "indices": idx}
    points = {"attributes": {"POSITION": add(QUAD_POS + 5)}, "mode": 0}
    tri_b = {"attributes": {"POSITION": pos, "NORMAL": up, "TEXCOORD_0": add(QUAD_UV / 2)}, "indices": idx}
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
           "nodes": [{"mesh": 0}, {"mesh": 1, "translation": [10, 0, 0]}, {"mesh": 1, "translation": [20, 0, 0]}],
           "meshes": [{"name": "a", "primitives": [tri_a, points]}, {"name": "b", "primitives": [tri_b]}],
           "buffers": [{"byteLength": len(data),
                        "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
           "bufferViews": views, "accessors": accessors}
    (tmp_path / "multi.gltf").write_text(json.dumps(doc))
    mesh = load_mesh(tmp_path / "multi.gltf")
    assert mesh.vertex_count == 16 and mesh.triangle_count == 6
    np.testing.assert_allclose(mesh.positions[12:], QUAD_POS + 5)
    assert mesh.parts[-1].topology == "point-list" and mesh.parts[-1].index_count == 4
    np.testing.assert_array_equal(mesh.all_indices()[mesh.parts[-1].first_index:], [12, 13, 14, 15])
    for offset in (0.0, 10.0, 20.0):
        part = np.flatnonzero(np.abs(mesh.positions[:, 0] - offset - 0.5) < 1)
        assert len(part) == 4
        local = mesh.positions[part] - [offset, 0, 0]
        k = np.argmin(np.linalg.norm(local[:, None] - QUAD_POS[None], axis=2), axis=1)  # which file vertex
        np.testing.assert_allclose(local, QUAD_POS[k], atol=1e-6)
        np.testing.assert_array_equal(mesh.uvs[part], QUAD_UV[k] if offset == 0 else QUAD_UV[k] / 2)


# ------------------------------------------------------------------ indices, normals


def test_index_type_switches_at_65535():
    """Largest index 65534 -> uint16 (0xFFFF stays free); 65535 -> uint32. index_bytes pads to 4 bytes."""
    assert index_dtype(65534) is np.uint16 and index_dtype(65535) is np.uint32
    for count, dtype in ((65535, np.uint16), (65536, np.uint32)):
        positions = np.c_[np.arange(count), np.arange(count) % 7, np.zeros(count)].astype(float)
        indices = np.array([[0, 1, count - 1]])
        mesh = build_mesh(positions, indices, generate_tangents=False)
        assert mesh.indices.dtype == dtype and mesh.index_format == dtype.__name__
        assert int(mesh.indices.max()) == count - 1
        assert len(mesh.index_bytes()) % 4 == 0
        np.testing.assert_array_equal(np.frombuffer(mesh.index_bytes(), dtype)[:3], [0, 1, count - 1])


def test_area_weighted_normal_analytic():
    """Vertex 0 joins a triangle of area 2 in the XY plane (normal +Z) and one of area 0.5 in the XZ plane
    (normal +Y): area weighting gives normalize(2 Z + 0.5 Y), unweighted averaging would give normalize(Z + Y)."""
    positions = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0], [0, 0, 1], [1, 0, 0]], float)
    indices = np.array([[0, 1, 2], [0, 3, 4]])
    n = area_weighted_normals(positions, indices)
    want = np.array([0, 0.5, 2]) / np.linalg.norm([0, 0.5, 2])
    np.testing.assert_allclose(n[0], want, atol=1e-6)
    np.testing.assert_allclose(n[[1, 2]], [[0, 0, 1]] * 2, atol=1e-7)
    np.testing.assert_allclose(n[[3, 4]], [[0, 1, 0]] * 2, atol=1e-7)


def test_missing_normals_on_a_sphere_point_outward(tmp_path):
    """An icosphere (trimesh.creation, 642 vertices) saved as OBJ without normals: computed normals match the
    position direction within 1 degree."""
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=2.0)
    lines = [f"v {x:.7f} {y:.7f} {z:.7f}" for x, y, z in sphere.vertices]
    lines += [f"f {a} {b} {c}" for a, b, c in sphere.faces + 1]
    (tmp_path / "s.obj").write_text("\n".join(lines) + "\n")
    mesh = load_mesh(tmp_path / "s.obj")
    radial = mesh.positions / np.linalg.norm(mesh.positions, axis=1, keepdims=True)
    assert mesh.vertex_count == 642
    assert np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", mesh.normals, radial), -1, 1))).max() < 1.0


# ------------------------------------------------------------------ errors


def expect_user_error(path, *fragments):
    with pytest.raises(UserError) as info:
        load_mesh(path)
    message = str(info.value)
    for fragment in (str(path), *fragments):
        assert fragment in message, f"{fragment!r} not in {message!r}"
    return message


def test_blender_and_unknown_formats_say_how_to_convert(tmp_path):
    (tmp_path / "model.blend").write_bytes(b"BLENDER-v300")
    expect_user_error(tmp_path / "model.blend", "Blender", "not supported", "glTF", "assimp export model.blend")
    expect_user_error(tmp_path / "model.xyz123", "unknown model format", ".obj", ".glb")


def test_missing_file(tmp_path):
    expect_user_error(tmp_path / "nope.obj", "not found")


@pytest.mark.parametrize("name, content, fragment", [
    ("garbage.glb", b"glTF\x02\0\0\0\xff\xff\xff\x7f\x10\0\0\0JSON{bad", "malformed"),
    ("garbage.gltf", b"{ this is not json", "malformed"),
    ("garbage.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1 2\n", "malformed"),
    ("empty.obj", b"", "empty"),
    ("lines.obj", b"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2\nl 2 3\n", "fewer than 3 vertices"),
    ("nan.obj", b"v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n", "NaN or infinite"),
    ("inf.obj", b"v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", "NaN or infinite"),
    ("empty.stl", b"solid x\nendsolid x\n", "empty"),
])
def test_bad_files_raise_user_errors_naming_the_file(tmp_path, name, content, fragment):
    (tmp_path / name).write_bytes(content)
    expect_user_error(tmp_path / name, fragment)


def test_gltf_attribute_count_mismatch_and_truncated_buffer(tmp_path):
    path = write_gltf(tmp_path / "bad.gltf", {"POSITION": QUAD_POS, "TANGENT": np.zeros((3, 4))}, QUAD_IDX)
    expect_user_error(path, "TANGENT has 3 elements")
    doc = json.loads(path.read_text())
    doc["accessors"][1]["count"] = 400  # runs past the end of the buffer
    path.write_text(json.dumps(doc))
    expect_user_error(path, "malformed")


# ------------------------------------------------------------------ scale, assets


def test_million_triangle_binary_ply_loads_vectorised(tmp_path):
    """1,000,000 triangles / 501,501 vertices written as binary PLY by numpy: loads with uint32 indices, exact
    topology, uvs converted (1e-7) and unit tangents. (No time assertion; it takes ~2 s on 2 cores.)"""
    g = proc.plane(4.0, 2.0, cols=1000, rows=500)
    vertex = np.empty(len(g.positions), [("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("s", "<f4"), ("t", "<f4")])
    vertex["x"], vertex["y"], vertex["z"] = g.positions.T
    vertex["s"], vertex["t"] = g.uvs[:, 0], 1.0 - g.uvs[:, 1]
    face = np.empty(len(g.indices), [("n", "u1"), ("i", "<i4", (3,))])
    face["n"], face["i"] = 3, g.indices
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertex)}\n"
              + "".join(f"property float {p}\n" for p in "xyzst")
              + f"element face {len(face)}\nproperty list uchar int vertex_indices\nend_header\n")
    (tmp_path / "big.ply").write_bytes(header.encode() + vertex.tobytes() + face.tobytes())
    mesh = load_mesh(tmp_path / "big.ply")
    assert mesh.triangle_count == 1_000_000 and mesh.vertex_count == 501_501
    assert mesh.indices.dtype == np.uint32
    np.testing.assert_array_equal(mesh.indices, g.indices)
    np.testing.assert_allclose(mesh.uvs, g.uvs, atol=1e-7)
    np.testing.assert_allclose(mesh.normals[::997], np.tile([0, 0, 1], (len(mesh.normals[::997]), 1)), atol=1e-6)
    np.testing.assert_allclose(mesh.tangents[::997], np.tile([1, 0, 0, 1], (len(mesh.tangents[::997]), 1)), atol=1e-6)


def test_assets_are_reproducible(tmp_path):
    """assets/make_assets.py regenerated into tmp_path: models byte-identical to the committed ones, PNG pixels
    identical (PNG bytes may legitimately differ between zlib versions)."""
    from wgpurender.core.files.imageio import load_png

    spec = importlib.util.spec_from_file_location("make_assets", ROOT / "assets" / "make_assets.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    written = module.generate(tmp_path)
    assert {p.name for p in written} >= {"brick_torus.glb", "brick_cube.obj", "brick_cube.mtl", "mirrored_quad.glb",
                                         "brick_albedo.png", "brick_normal.png", "brick_roughness.png",
                                         "dome_normal.png", "mirror_albedo.png"}
    for rel in written:
        committed, fresh = ROOT / "assets" / rel, tmp_path / rel
        if rel.suffix == ".png":
            np.testing.assert_array_equal(load_png(committed), load_png(fresh))
        else:
            assert committed.read_bytes() == fresh.read_bytes(), rel


def test_committed_obj_asset_loads_with_its_textures():
    """brick_cube.obj: 24 vertices / 12 triangles equal procedural.box() (uvs back in our convention, 1e-6), uint16
    indices, every referenced texture exists and decodes as 512x512."""
    mesh = load_mesh(ROOT / "assets" / "models" / "brick_cube.obj")
    box = proc.box()
    np.testing.assert_allclose(mesh.positions, box.positions, atol=1e-6)
    np.testing.assert_allclose(mesh.uvs, box.uvs, atol=1e-6)
    np.testing.assert_allclose(mesh.normals, box.normals, atol=1e-6)
    assert mesh.index_format == "uint16" and mesh.triangle_count == 12
    from wgpurender.core.scene.texture_pixels import load_image

    textures = obj_mtl_entry(ROOT / "assets" / "models" / "brick_cube.obj").textures
    assert set(textures) == {"base_color", "normal", "roughness"}
    for path in textures.values():
        assert load_image(path).shape == (512, 512, 4)


def test_glb_embedded_texture_is_returned_as_bytes(tmp_path):
    """A GLB whose base-colour image lives in a bufferView (no file): the scene's material names it as
    ``tex.glb#images[0]`` and the texture loader decodes it to the exact pixels written (2x3 RGBA)."""
    import io

    from PIL import Image

    pixels = np.arange(2 * 3 * 4, dtype=np.uint8).reshape(2, 3, 4) * 10
    png = io.BytesIO()
    Image.fromarray(pixels, "RGBA").save(png, format="PNG")
    path = write_gltf(tmp_path / "tex.glb", {"POSITION": QUAD_POS, "TEXCOORD_0": QUAD_UV}, QUAD_IDX, material=True)
    raw = path.read_bytes()
    json_len = struct.unpack_from("<I", raw, 12)[0]
    doc = json.loads(raw[20:20 + json_len])
    binary = raw[20 + json_len + 8:]
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(png.getvalue())})
    doc["images"][0] = {"bufferView": len(doc["bufferViews"]) - 1, "mimeType": "image/png"}
    write_container(path, doc, binary + png.getvalue())
    from wgpurender.core.scene.gltf_materials import embedded_image_path, model_materials
    from wgpurender.core.scene.texture_pixels import load_image

    albedo = model_materials(path, "tex").materials[0].albedo_map
    assert albedo == embedded_image_path(path, 0)
    np.testing.assert_array_equal(load_image(albedo), pixels)


@pytest.mark.parametrize("statement, name", [
    ("map_Kd textures/brick albedo.png", "textures/brick albedo.png"),  # Blender: a name with spaces, unquoted
    ("map_Kd -bm 1.0 -o 0.5 0.5 my  tex.png", "my  tex.png"),  # options first; the name's own spacing kept
    ("map_Kd -clamp on -s 2 tex 1.png", "tex 1.png"),  # -s with one value, then a name that starts like a word
    ("map_Kd plain.png", "plain.png"),
])
def test_a_map_file_name_is_the_rest_of_the_line_after_its_options(tmp_path, statement, name):
    """The MTL's texture path is what follows the map options, spaces kept (it was the last word only: a Blender
    material whose texture's name has a space read 'albedo.png' for 'brick albedo.png')."""
    (tmp_path / "m.mtl").write_text(f"newmtl m\n{statement}\n")
    texture = parse_mtl(tmp_path / "m.mtl")["m"].textures["base_color"]
    assert texture == (tmp_path / name).resolve()

