"""The normal matrix as the GPU should receive it: the sign-corrected cofactor, scaled to a largest entry of 1.

transforms.normal_matrix gives cof(M) * sign(det M): no division, so it is finite for near-singular scales where
the inverse-transpose blows up. Its entries are products of two scale factors, though: a model squashed to 1e-20
on two axes has cofactor entries of 1e-40, a float32 denormal that GPUs flush to zero. Only the direction of a
transformed normal matters (the shader normalises it), so dividing the whole matrix by its largest entry changes
nothing in exact arithmetic and keeps every entry float32-friendly.
"""

from __future__ import annotations

import numpy as np

from wgpurender.core.view.transforms import normal_matrix


def gpu_normal_matrix(world: np.ndarray) -> np.ndarray:
    """normal_matrix(world) / max |entry| (float64 3x3); a zero matrix (fully singular world) stays zero."""
    n = normal_matrix(world)
    biggest = np.abs(n).max()
    return n / biggest if biggest > 0 else n


def analytic_normals(scales, rotation: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Reference normals of unit normals under world = rotation @ diag(scales), float64.

    The inverse-transpose of R diag(s) is R diag(1/s) exactly (R orthonormal), so n' = normalize(R (n / s)).
    Evaluated with each component scaled first so 1/s = 1e20 cannot overflow the float64 dot product.
    """
    s = np.asarray(scales, dtype=np.float64)
    v = np.asarray(normals, dtype=np.float64) / s
    v = v / np.abs(v).max(axis=1, keepdims=True)
    v = v / np.linalg.norm(v, axis=1, keepdims=True)
    return v @ np.asarray(rotation, dtype=np.float64)[:3, :3].T
