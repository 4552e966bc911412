"""Mirrored UVs: tangent handedness (w) and the reconstructed bitangent agree with the analytic frame.

Quads in the z = 0 plane, normal +z, in this project's UV convention (v = 0 at the top of the image, see
wgpurender/core/models/tangents.py). Analytic frame: t = dP/du normalised; "up in the image" = -dP/dv normalised; the
bitangent a shader reconstructs, b = w * cross(n, t), must equal "up in the image". Tolerance 1e-6 (float32 output).

- plain quad (u = x, v = 1 - y): t = +x, b = +y, w = +1;
- mirrored quad (u = 1 - x): t = -x, w = -1, and b is still +y;
- a symmetric "model" of two quads sharing an edge, the right one mirrored (a character's two halves): after
  split_mirrored_vertices each side gets its own frame.
- counter-example: ignoring w (w = +1 everywhere) flips the mirrored side's bitangent (180 degrees).
"""

from __future__ import annotations

import numpy as np

from wgpurender.core.models.tangents import face_uv_frames, split_mirrored_vertices, vertex_tangents

QUAD = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
QUAD_IDX = np.array([[0, 1, 2], [0, 2, 3]])
NORMALS = np.tile([0.0, 0.0, 1.0], (4, 1))


def analytic_frame(positions, uvs, tri):
    """(dP/du, -dP/dv) of one triangle, unit, float64: solve [e1 e2] = [dP/du dP/dv] [duv1 duv2]."""
    p, uv = positions[tri], uvs[tri]
    edges = np.stack([p[1] - p[0], p[2] - p[0]], axis=1)  # 3x2
    duv = np.stack([uv[1] - uv[0], uv[2] - uv[0]], axis=1)  # 2x2
    d = edges @ np.linalg.inv(duv)  # columns dP/du, dP/dv
    t, up = d[:, 0], -d[:, 1]
    return t / np.linalg.norm(t), up / np.linalg.norm(up)


def bitangent(tangents, normals, ignore_w=False):
    w = 1.0 if ignore_w else tangents[:, 3:4]
    return w * np.cross(normals, tangents[:, :3])


def test_plain_quad():
    uvs = np.stack([QUAD[:, 0], 1 - QUAD[:, 1]], axis=1)
    t = vertex_tangents(QUAD, NORMALS, uvs, QUAD_IDX)
    t_ref, up_ref = analytic_frame(QUAD, uvs, QUAD_IDX[0])
    assert np.allclose(t_ref, [1, 0, 0]) and np.allclose(up_ref, [0, 1, 0])
    assert np.allclose(t[:, :3], t_ref, atol=1e-6) and (t[:, 3] == 1).all()
    assert np.allclose(bitangent(t, NORMALS), up_ref, atol=1e-6)


def test_mirrored_quad():
    uvs = np.stack([1 - QUAD[:, 0], 1 - QUAD[:, 1]], axis=1)
    t = vertex_tangents(QUAD, NORMALS, uvs, QUAD_IDX)
    t_ref, up_ref = analytic_frame(QUAD, uvs, QUAD_IDX[0])
    assert np.allclose(t_ref, [-1, 0, 0]) and np.allclose(up_ref, [0, 1, 0])
    assert np.allclose(t[:, :3], t_ref, atol=1e-6) and (t[:, 3] == -1).all()
    assert np.allclose(bitangent(t, NORMALS), up_ref, atol=1e-6)
    assert np.allclose(bitangent(t, NORMALS, ignore_w=True), -up_ref, atol=1e-6)  # counter-example


def test_symmetric_model_with_shared_seam():
    """Left quad x in [-1, 0]: u = x + 1; right quad x in [0, 1] mirrors it (u = 1 - x); they share the seam x = 0."""
    positions = np.array([[-1, 0, 0], [0, 0, 0], [1, 0, 0], [-1, 1, 0], [0, 1, 0], [1, 1, 0]], dtype=np.float64)
    uvs = np.stack([1 - np.abs(positions[:, 0]), 1 - positions[:, 1]], axis=1)
    indices = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    _, _, _, handed = face_uv_frames(positions, uvs, indices)
    assert list(handed) == [1, 1, -1, -1]
    new_idx, source = split_mirrored_vertices(indices, handed, len(positions))
    assert len(source) == 8  # the two seam vertices were duplicated
    p, uv, n = positions[source], uvs[source], np.tile([0.0, 0.0, 1.0], (len(source), 1))
    t = vertex_tangents(p, n, uv, new_idx)
    for face in range(len(new_idx)):
        t_ref, up_ref = analytic_frame(p, uv, new_idx[face])
        corners = new_idx[face]
        assert np.allclose(t[corners, :3], t_ref, atol=1e-6)
        assert np.allclose(bitangent(t[corners], n[corners]), up_ref, atol=1e-6)
        assert (t[corners, 3] == handed[face]).all()
