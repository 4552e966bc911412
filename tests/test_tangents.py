"""Tangent frames (core/models/tangents.py) against analytic directions, handedness, degenerate input and glTF files.

Tolerances: flat (planar) cases are exact up to float32 rounding (1e-6); the torus compares against its analytic
dP/du: 1e-3 rad at interior vertices (measured 5.9e-4: each quad is split along one diagonal, so vertex
neighbourhoods are not quite symmetric and chord directions do not cancel exactly) and half an angular step (1.9 deg)
at the UV seam, where only one side's triangles exist. Normal-map baking is checked against the closed form of a
linear ramp.
"""

from __future__ import annotations

import base64
import json

import numpy as np
import pytest

from wgpurender.core.models import procedural as proc
from wgpurender.core.models.mesh import build_mesh, load_mesh
from wgpurender.core.models.tangents import (
    area_weighted_normals,
    face_uv_frames,
    split_mirrored_vertices,
    vertex_tangents,
)


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def angle_between(a, b):
    """Row-wise angle in radians, float64 and well-conditioned near 0 (arctan2 of |cross| and dot)."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))


def assert_valid_frames(tangents, normals):
    """Finite, unit xyz, orthogonal to the normal, w exactly +-1."""
    assert np.all(np.isfinite(tangents))
    np.testing.assert_allclose(np.linalg.norm(tangents[:, :3], axis=1), 1.0, atol=1e-6)
    assert np.abs(np.einsum("ij,ij->i", tangents[:, :3], normals)).max() < 1e-6
    assert set(np.unique(tangents[:, 3])) <= {-1.0, 1.0}


@pytest.mark.parametrize("shear", [0.0, 0.4])
def test_flat_quad_tangent_is_the_analytic_du_direction(shear):
    """A quad in a rotated plane with an affine UV mapping uv = A @ (x, y) + c (A rotates by 30 deg, scales,
    shears and flips v so v grows downwards). dP/du is the first column of A^-1, mapped into 3D: t must equal
    its direction, w must be +1 (unmirrored) and b = w * cross(n, t) must point along -dP/dv."""
    theta = np.radians(30)
    a = np.array([[np.cos(theta), np.sin(theta) + shear], [np.sin(theta), -np.cos(theta)]]) * [[0.5], [0.8]]
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    uv = xy @ a.T + [0.2, 0.7]
    r = rotation([1, 2, 3], 0.7)
    positions = np.c_[xy, np.zeros(4)] @ r.T
    indices = np.array([[0, 1, 2], [0, 2, 3]])
    normals = np.tile(r[:, 2], (4, 1))
    inv = np.linalg.inv(a)
    dp_du, dp_dv = r[:, :2] @ inv[:, 0], r[:, :2] @ inv[:, 1]
    want_t = dp_du / np.linalg.norm(dp_du)

    tangents = vertex_tangents(positions, normals, uv, indices)
    np.testing.assert_allclose(tangents[:, :3], np.tile(want_t, (4, 1)), atol=1e-6)
    np.testing.assert_array_equal(tangents[:, 3], 1.0)
    b = tangents[:, 3:] * np.cross(normals, tangents[:, :3])
    assert np.all(b @ -dp_dv > 0)


def test_mirrored_uvs_give_negative_w_on_the_mirrored_half():
    """procedural.mirrored_quad: left half (x < 0) has u mirrored. Expected analytic frames: left t = -X, w = -1;
    right t = +X, w = +1; in both halves b = w * cross(n, t) = +Y (up in the image)."""
    for split in (True, False):
        q = proc.mirrored_quad(split_seam=split)
        mesh = build_mesh(q.positions, q.indices, q.normals, q.uvs)
        left = np.isin(np.arange(mesh.vertex_count), mesh.indices[:2].ravel())
        right = np.isin(np.arange(mesh.vertex_count), mesh.indices[2:].ravel())
        assert not np.any(left & right), "seam vertices must be split, one copy per handedness"
        np.testing.assert_array_equal(mesh.tangents[left, 3], -1.0)
        np.testing.assert_array_equal(mesh.tangents[right, 3], 1.0)
        np.testing.assert_allclose(mesh.tangents[left, :3], np.tile([-1, 0, 0], (left.sum(), 1)), atol=1e-6)
        np.testing.assert_allclose(mesh.tangents[right, :3], np.tile([1, 0, 0], (right.sum(), 1)), atol=1e-6)
        b = mesh.tangents[:, 3:] * np.cross(mesh.normals, mesh.tangents[:, :3])
        np.testing.assert_allclose(b, np.tile([0, 1, 0], (mesh.vertex_count, 1)), atol=1e-6)
        assert mesh.vertex_count == 8


def test_split_mirrored_vertices_duplicates_only_conflicted_vertices():
    """Shared seam: vertices 1 and 4 are used by both halves -> two new vertices copying 1 and 4; the others and
    faces of the +1 side keep their indices. Without conflicts nothing changes."""
    q = proc.mirrored_quad(split_seam=False)
    _, _, _, handed = face_uv_frames(q.positions, q.uvs, q.indices)
    np.testing.assert_array_equal(handed, [-1, -1, 1, 1])
    indices, source = split_mirrored_vertices(q.indices, handed, 6)
    assert len(source) == 8 and sorted(np.bincount(source, minlength=6).tolist()) == [1, 1, 1, 1, 2, 2]
    np.testing.assert_array_equal(source[indices], q.indices)  # every corner still points at the same position
    left, right = set(indices[:2].ravel()), set(indices[2:].ravel())
    assert not left & right

    p = proc.plane(cols=3, rows=2)
    same_indices, same_source = split_mirrored_vertices(p.indices, np.ones(len(p.indices)), len(p.positions))
    np.testing.assert_array_equal(same_indices, p.indices)
    np.testing.assert_array_equal(same_source, np.arange(len(p.positions)))


def test_degenerate_uv_and_zero_area_triangles_stay_finite():
    """Triangles with all-equal UVs, collinear UVs, collinear positions and coincident positions: every tangent is
    finite, unit, orthogonal to its (tilted, per-vertex) normal and w = +-1; the healthy triangle is unaffected."""
    positions = np.array([
        [0, 0, 0], [1, 0, 0], [0, 1, 0],          # healthy, u along +X
        [2, 0, 0], [3, 0, 0], [2, 1, 0],          # UVs all equal
        [4, 0, 0], [5, 0, 0], [4, 1, 0],          # UVs collinear
        [6, 0, 0], [7, 0, 0], [8, 0, 0],          # positions collinear (zero area)
        [9, 0, 0], [9, 0, 0], [9, 0, 0],          # positions coincident
    ], float)
    uvs = np.array([
        [0, 1], [1, 1], [0, 0],
        [0.3, 0.3], [0.3, 0.3], [0.3, 0.3],
        [0, 0], [0.5, 0.5], [1, 1],
        [0, 1], [1, 1], [0, 0],
        [0, 1], [1, 1], [0, 0],
    ], float)
    indices = np.arange(15).reshape(5, 3)
    normals = np.tile([0.0, 0.0, 1.0], (15, 1))
    normals[3:] = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
    tangents = vertex_tangents(positions, normals, uvs, indices)
    assert_valid_frames(tangents, normals)
    np.testing.assert_allclose(tangents[:3], np.tile([1, 0, 0, 1], (3, 1)), atol=1e-6)
    np.testing.assert_array_equal(tangents[3:, 3], 1.0)

    # area-weighted normals of the degenerate triangles fall back to +Z, and build_mesh copes end to end
    mesh = build_mesh(positions, indices, uvs=uvs)
    assert_valid_frames(mesh.tangents, mesh.normals)
    np.testing.assert_allclose(area_weighted_normals(positions, indices)[9:], np.tile([0, 0, 1], (6, 1)))


def test_torus_tangents_match_analytic_du_direction():
    t = proc.torus()
    mesh = build_mesh(t.positions, t.indices, t.normals, t.uvs)
    assert mesh.vertex_count == len(t.positions)  # no mirrored triangles, nothing split
    want = proc.torus_tangent(t)
    angle = angle_between(mesh.tangents[:, :3], want)
    seam = np.isclose(t.uvs[:, 0], 0) | np.isclose(t.uvs[:, 0], 5.0)
    assert angle[~seam].max() < 1e-3
    assert angle[seam].max() < np.radians(360 / 96 / 2) + 1e-4
    np.testing.assert_array_equal(mesh.tangents[:, 3], 1.0)
    assert_valid_frames(mesh.tangents, mesh.normals)


def _gltf_with_tangents(path, tangents):
    """A hand-written .gltf (JSON + base64 buffer): one quad in z = 0 with uvs and the given TANGENT values."""
    pos = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    nrm = np.tile(np.float32([0, 0, 1]), (4, 1))
    uv = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
    idx = np.array([0, 1, 2, 0, 2, 3], np.uint16)
    blobs = [pos, nrm, uv, np.asarray(tangents, np.float32), idx]
    data, views, accessors = b"", [], []
    for k, blob in enumerate(blobs):
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": blob.nbytes})
        data += blob.tobytes() + b"\0" * (-blob.nbytes % 4)
        kind = "SCALAR" if blob.ndim == 1 else f"VEC{blob.shape[1]}"
        accessors.append({"bufferView": k, "componentType": 5123 if blob.dtype == np.uint16 else 5126,
                          "count": len(blob), "type": kind})
    accessors[0].update(min=[0, 0, 0], max=[1, 1, 0])
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TANGENT": 3},
                                    "indices": 4}]}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": views, "accessors": accessors,
    }
    path.write_text(json.dumps(doc))
    return path


def test_tangents_read_from_gltf_equal_the_files(tmp_path):
    """The file's TANGENT is used as is (exact float32 equality), even where generation would give another frame:
    these tangents are +Y with w = -1 and one vertex at 45 deg, while generated ones would be +X with w = +1."""
    s = np.sqrt(0.5)
    file_tangents = np.array([[0, 1, 0, -1], [0, 1, 0, -1], [s, s, 0, 1], [0, 1, 0, -1]], np.float32)
    mesh = load_mesh(_gltf_with_tangents(tmp_path / "quad.gltf", file_tangents))
    assert mesh.tangents_source == "file"
    np.testing.assert_array_equal(mesh.tangents, file_tangents)
    bare = build_mesh(mesh.positions, mesh.indices, mesh.normals, mesh.uvs)
    np.testing.assert_allclose(bare.tangents, np.tile([1, 0, 0, 1], (4, 1)), atol=1e-6)


def test_committed_assets_have_the_documented_frames():
    """assets/models: the torus's file tangents agree with the analytic dP/du (same bounds as the torus test) and
    are all w = +1; the mirrored quad's file tangents have w = -1 exactly on x < 0 and +1 on x > 0."""
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent / "assets" / "models"
    torus = load_mesh(root / "brick_torus.glb")
    assert torus.tangents_source == "file"
    t = proc.torus()
    np.testing.assert_allclose(torus.positions, t.positions, atol=1e-6)
    angle = angle_between(torus.tangents[:, :3], proc.torus_tangent(t))
    assert angle.max() < np.radians(360 / 96 / 2) + 1e-4
    np.testing.assert_array_equal(torus.tangents[:, 3], 1.0)

    quad = load_mesh(root / "mirrored_quad.glb")
    assert quad.tangents_source == "file"
    x = quad.positions[:, 0]
    left = np.isin(np.arange(quad.vertex_count), quad.indices[:2].ravel())
    np.testing.assert_array_equal(quad.tangents[:, 3], np.where(left, -1.0, 1.0))
    assert np.all(x[left] <= 0) and np.all(x[~left] >= 0)


def test_normal_map_from_height_ramp_matches_closed_form():
    """h = x / W (rising to the right) -> n = normalize(-s / W, 0, 1): tilted toward -X. h = row / H (rising down the
    image) -> n = normalize(0, +s / H, 1): tilted toward +Y, i.e. up in the image (OpenGL convention). Interior
    texels only (the ramp wraps at the border). Encode/decode round trip within 1/127.5 per component."""
    size, s = 64, 12.0
    ramp = np.tile(np.arange(size, dtype=float) / size, (size, 1))
    n = proc.normals_from_height(ramp, s)[2:-2, 2:-2]
    want = np.array([-s / size, 0, 1]) / np.linalg.norm([-s / size, 0, 1])
    np.testing.assert_allclose(n, np.broadcast_to(want, n.shape), atol=1e-12)
    n = proc.normals_from_height(ramp.T, s)[2:-2, 2:-2]
    want = np.array([0, s / size, 1]) / np.linalg.norm([0, s / size, 1])
    np.testing.assert_allclose(n, np.broadcast_to(want, n.shape), atol=1e-12)
    decoded = proc.decode_normal_map(proc.encode_normal_map(n))
    assert np.abs(decoded - n).max() < 1 / 127.5
