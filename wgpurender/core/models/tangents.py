"""Per-vertex tangent frames for normal mapping, from positions, normals and UVs (vectorised numpy).

Conventions (the glTF ones, so generated tangents agree with tangents read from glTF files):

- uvs are in this project's mesh convention: v = 0 at the TOP of the image, v grows downwards (see mesh.py).
- tangent = (t.xyz, w): t is the surface direction of +u, unit length, orthogonal to the vertex normal n.
- bitangent ``b = w * cross(n, t)`` is the surface direction of "up in the image", i.e. of -v (decreasing v).
- handedness ``w = sign(dot(cross(n, t), b_up))`` with b_up the accumulated surface direction of -v: +1 for an
  ordinary mapping (image seen upright and unmirrored from the front), -1 on mirrored UV islands.
- normal maps are tangent-space, +Y up (OpenGL / glTF convention): a shader decodes ``m = texel * 2 - 1`` and
  uses ``normalize(t * m.x + b * m.y + n * m.z)`` with ``b = w * cross(n, t)``.

A vertex shared by triangles of opposite handedness cannot have one tangent; :func:`split_mirrored_vertices`
duplicates such vertices first (what MikkTSpace-based exporters produce).
"""

from __future__ import annotations

import numpy as np

EPS = 1e-12


def _accumulate(indices: np.ndarray, values: np.ndarray, n_vertices: int) -> np.ndarray:
    """Sum per-triangle (F, 3) vectors into each of the triangle's three vertices -> (n_vertices, 3)."""
    corners = indices.reshape(-1)
    per_corner = np.repeat(values, 3, axis=0)
    return np.stack([np.bincount(corners, per_corner[:, k], minlength=n_vertices) for k in range(3)], axis=1)


def face_normals_area(positions: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """Unnormalised face normals: cross(p1 - p0, p2 - p0), length = twice the triangle area (float64)."""
    p = np.asarray(positions, np.float64)[indices]
    return np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])


def perpendicular(n: np.ndarray) -> np.ndarray:
    """Some unit vector perpendicular to each unit vector in n (N, 3): cross with the least-aligned axis."""
    n = np.asarray(n, np.float64)
    axis = np.zeros_like(n)
    axis[np.arange(len(n)), np.argmin(np.abs(n), axis=1)] = 1.0
    t = np.cross(n, axis)
    return t / np.maximum(np.linalg.norm(t, axis=1, keepdims=True), EPS)


def area_weighted_normals(positions: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """Vertex normals as the area-weighted sum of adjacent face normals, unit length (float32).

    Vertices with no non-degenerate adjacent triangle get +Z, so the result is always finite.
    """
    summed = _accumulate(indices, face_normals_area(positions, indices), len(positions))
    length = np.linalg.norm(summed, axis=1, keepdims=True)
    out = np.where(length > EPS, summed / np.maximum(length, EPS), np.array([0.0, 0.0, 1.0]))
    return out.astype(np.float32)


def face_uv_frames(positions: np.ndarray, uvs: np.ndarray, indices: np.ndarray):
    """Per-triangle surface directions of +u and of -v ("up" in the image), their weight and handedness.

    Solves ``e1 = du1*T + dv1*B``, ``e2 = du2*T + dv2*B`` for T (dP/du) and B (dP/dv). Weight is the triangle's
    area, 0 for triangles whose UV area or position area is (numerically) zero, so those add nothing.
    Returns (t (F,3), b_up (F,3) = -B normalised, weight (F,), handed (F,)): handed is the sign of
    dot(cross(face normal, t), b_up) = -sign(signed UV area), +1 for an unmirrored mapping, 0 when degenerate.
    """
    p = np.asarray(positions, np.float64)[indices]
    uv = np.asarray(uvs, np.float64)[indices]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    d1, d2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    area = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
    # relative thresholds: a UV triangle is degenerate when its area is tiny against its edge lengths
    uv_scale = np.maximum(np.einsum("ij,ij->i", d1, d1), np.einsum("ij,ij->i", d2, d2))
    pos_scale = np.maximum(np.einsum("ij,ij->i", e1, e1), np.einsum("ij,ij->i", e2, e2))
    good = (np.abs(det) > 1e-10 * uv_scale) & (area > 1e-12 * pos_scale) & (uv_scale > 0) & (pos_scale > 0)
    safe = np.where(good, det, 1.0)[:, None]
    t = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) / safe
    b = (e1 * d2[:, 0:1] - e2 * d1[:, 0:1]) / safe  # -dP/dv
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), EPS)
    b /= np.maximum(np.linalg.norm(b, axis=1, keepdims=True), EPS)
    weight = np.where(good, area, 0.0)
    return t, b, weight, np.where(good, -np.sign(det), 0.0)


def vertex_tangents(positions: np.ndarray, normals: np.ndarray, uvs: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """(N, 4) float32 tangents: xyz unit and orthogonal to the normal, w = +1 or -1 (handedness).

    Face directions are accumulated with area weights, then Gram-Schmidt orthogonalised against the vertex normal.
    Where nothing usable was accumulated (only degenerate triangles, or t parallel to n) the tangent is some unit
    vector perpendicular to n with w = +1. Always finite for finite unit normals.
    """
    indices = np.asarray(indices, np.int64).reshape(-1, 3)
    n = np.asarray(normals, np.float64)
    n = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), EPS)
    t_f, b_f, w_f, _ = face_uv_frames(positions, uvs, indices)
    t = _accumulate(indices, t_f * w_f[:, None], len(n))
    b = _accumulate(indices, b_f * w_f[:, None], len(n))
    t -= n * np.einsum("ij,ij->i", n, t)[:, None]
    length = np.linalg.norm(t, axis=1, keepdims=True)
    ok = length[:, 0] > 1e-9
    t = np.where(ok[:, None], t / np.maximum(length, EPS), perpendicular(n))
    handed = np.einsum("ij,ij->i", np.cross(n, t), b)
    w = np.where(ok & (handed < 0.0), -1.0, 1.0)
    return np.concatenate([t, w[:, None]], axis=1).astype(np.float32)


def split_mirrored_vertices(indices: np.ndarray, face_sign: np.ndarray, n_vertices: int):
    """Duplicate vertices used by triangles of both UV handedness, so each copy gets one tangent frame.

    face_sign: (F,) handedness from face_uv_frames, +1 / -1 / 0 (degenerate: joins the +1 copy).
    Returns (new indices (F, 3) int64, source (M,) int64: new vertex k copies old vertex source[k]).
    When no vertex is shared across handedness the indices and vertex order come back unchanged (source = arange).
    """
    indices = np.asarray(indices, np.int64).reshape(-1, 3)
    corner_sign = np.repeat(np.asarray(face_sign) < 0, 3)
    corners = indices.reshape(-1)
    has_neg = np.bincount(corners[corner_sign], minlength=n_vertices) > 0
    has_pos = np.bincount(corners[~corner_sign & (np.repeat(face_sign, 3) > 0)], minlength=n_vertices) > 0
    if not np.any(has_neg & has_pos):
        return indices, np.arange(n_vertices, dtype=np.int64)
    # degenerate corners (sign 0) of a conflicted vertex go with the positive copy
    key = corners * 2 + (corner_sign & has_pos[corners] & has_neg[corners])
    all_keys = np.concatenate([np.arange(n_vertices, dtype=np.int64) * 2, key])  # keep unused vertices too
    unique, inverse = np.unique(all_keys, return_inverse=True)
    return inverse[n_vertices:].reshape(-1, 3), unique // 2
