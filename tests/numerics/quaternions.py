"""Quaternions (w, x, y, z), unit length, acting as rotations; conversions that stay exact near 180 degrees.

Convention: q = (w, x, y, z) with w = cos(angle/2), (x, y, z) = sin(angle/2) * axis, so the matrix is the same
rotation as :func:`wgpurender.core.view.transforms.rotate(axis, angle)` (right-hand rule, column vectors).

Why Shepperd's method: the textbook conversion reads w from the trace, w = sqrt(1 + trace) / 2, and divides
the off-diagonal differences by 4w. Near a half turn the trace is -1, w -> 0, and the division amplifies rounding
error without bound (at exactly 180 degrees it divides 0 by 0). Shepperd's method takes the square root of the
largest of (1 + trace, 1 + 2*m00 - trace, ...) instead, so the divisor is always at least 1/2 and the result keeps
full precision for every rotation. :func:`from_matrix_naive` keeps the textbook version as the counter-example.
"""

from __future__ import annotations

import numpy as np


def normalize(q) -> np.ndarray:
    """q / |q| (float64); the canonical sign has w >= 0 (q and -q are the same rotation)."""
    q = np.asarray(q, dtype=np.float64)
    n = np.linalg.norm(q)
    if not np.isfinite(n) or n == 0:
        raise ValueError(f"cannot normalise quaternion {q}")
    return q / n


def canonical(q) -> np.ndarray:
    """The representative with w >= 0 (ties broken on the first non-zero component), for comparisons."""
    q = np.asarray(q, dtype=np.float64)
    for c in q:
        if c != 0:
            return q if c > 0 else -q
    return q


def from_axis_angle(axis, angle_rad: float) -> np.ndarray:
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    return np.concatenate([[np.cos(angle_rad / 2)], np.sin(angle_rad / 2) * a])


def to_matrix(q, dtype=np.float64) -> np.ndarray:
    """3x3 rotation matrix of a quaternion (normalised first, so any non-zero q gives a rotation), in ``dtype``."""
    w, x, y, z = normalize(q).astype(dtype)
    one, two = dtype(1), dtype(2)
    return np.array(
        [
            [one - two * (y * y + z * z), two * (x * y - w * z), two * (x * z + w * y)],
            [two * (x * y + w * z), one - two * (x * x + z * z), two * (y * z - w * x)],
            [two * (x * z - w * y), two * (y * z + w * x), one - two * (x * x + y * y)],
        ],
        dtype=dtype,
    )


def from_matrix(m) -> np.ndarray:
    """Unit quaternion of a 3x3 (or the 3x3 of a 4x4) rotation matrix, Shepperd's method, w >= 0."""
    m = np.asarray(m, dtype=np.float64)[:3, :3]
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    candidates = (1 + tr, 1 + 2 * m[0, 0] - tr, 1 + 2 * m[1, 1] - tr, 1 + 2 * m[2, 2] - tr)
    k = int(np.argmax(candidates))
    s = 2.0 * np.sqrt(candidates[k])  # = 4 * |component k|, >= 1 because the largest candidate is >= 1
    if k == 0:
        q = [s / 4, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    elif k == 1:
        q = [(m[2, 1] - m[1, 2]) / s, s / 4, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
    elif k == 2:
        q = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, s / 4, (m[1, 2] + m[2, 1]) / s]
    else:
        q = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, s / 4]
    return canonical(normalize(q))


def from_matrix_naive(m, dtype=np.float32) -> np.ndarray:
    """The textbook trace-only conversion (counter-example): w = sqrt(1 + trace) / 2, xyz = differences / 4w.

    Computed in ``dtype`` (float32 like a shader would); loses all precision near 180 degrees.
    """
    m = np.asarray(m, dtype=dtype)[:3, :3]
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.sqrt(np.maximum(dtype(1) + m[0, 0] + m[1, 1] + m[2, 2], dtype(0))) / dtype(2)
        d = dtype(4) * w
        q = np.array([w, (m[2, 1] - m[1, 2]) / d, (m[0, 2] - m[2, 0]) / d, (m[1, 0] - m[0, 1]) / d])
    return q.astype(np.float64)


def multiply(a, b, dtype=np.float64) -> np.ndarray:
    """Hamilton product a * b (apply b, then a), computed in ``dtype``."""
    w1, x1, y1, z1 = np.asarray(a, dtype=dtype)
    w2, x2, y2, z2 = np.asarray(b, dtype=dtype)
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ],
        dtype=dtype,
    )


def slerp(a, b, t: float) -> np.ndarray:
    """Spherical interpolation along the shorter arc; falls back to normalised lerp when a ~ b."""
    a, b = normalize(a), normalize(b)
    dot = float(a @ b)
    if dot < 0:
        b, dot = -b, -dot
    if dot > 0.9995:  # sin(theta) ~ 0: lerp is exact to rounding and avoids 0/0
        return normalize(a + t * (b - a))
    theta = np.arccos(dot)
    return (np.sin((1 - t) * theta) * a + np.sin(t * theta) * b) / np.sin(theta)


def orthonormalize(m) -> np.ndarray:
    """The rotation nearest to ``m`` (polar decomposition via SVD), same dtype as ``m``; det forced to +1."""
    m = np.asarray(m)
    u, _, vt = np.linalg.svd(m[:3, :3].astype(np.float64))
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] = -u[:, -1]
        r = u @ vt
    return r.astype(m.dtype)


def orthonormality_error(m) -> float:
    """||R^T R - I|| (Frobenius), computed in float64."""
    r = np.asarray(m, dtype=np.float64)[:3, :3]
    return float(np.linalg.norm(r.T @ r - np.eye(3)))
