"""Camera and model matrices in float64 numpy, and the one place they become GPU bytes.

Conventions (the same as GLM with GLM_FORCE_DEPTH_ZERO_TO_ONE, right-handed):
- matrices act on column vectors: ``clip = proj @ view @ world @ p``;
- the camera looks down -z in view space; clip-space depth runs 0 (near) .. 1 (far);
- numpy stores them row-major, WGSL and GLSL read column-major, so
  :func:`to_gpu` transposes, and it is the only function that does.

No Y flip: wgpu's NDC has y up and its framebuffer origin at the top-left, and it
maps NDC y=+1 to the top row itself. The Vulkan tutorial multiplies GLM's
``proj[1][1]`` by -1 because Vulkan's NDC has y pointing down; on wgpu that flip
would turn the image upside down.
"""

from __future__ import annotations

import numpy as np


def _as3(v) -> np.ndarray:
    return np.asarray(v, dtype=np.float64).reshape(3)


def perspective(fov_y_deg: float, aspect: float, near: float, far: float, *, reverse_z: bool = False) -> np.ndarray:
    """Right-handed perspective projection with depth 0..1 (or 1..0 when ``reverse_z``).

    Reverse-Z puts depth 1 at the near plane and 0 at the far plane, which spreads
    float32 depth precision evenly in log space (use with depth_compare "greater").
    ``far = inf`` is the limit far -> infinity (a glTF camera without zfar): depth 1 - near / distance.
    """
    if not (0 < near < far) or aspect <= 0 or not (0 < fov_y_deg < 180):
        raise ValueError(f"bad perspective: fov {fov_y_deg}, aspect {aspect}, near {near}, far {far}")
    f = 1.0 / np.tan(np.radians(fov_y_deg) / 2.0)
    m = np.zeros((4, 4))
    m[0, 0] = f / aspect
    m[1, 1] = f
    m[3, 2] = -1.0
    if np.isinf(far):  # far / (near - far) -> -1 and far near / (near - far) -> -near (reversed: 0 and near)
        m[2, 2], m[2, 3] = (0.0, near) if reverse_z else (-1.0, -near)
    elif reverse_z:
        m[2, 2] = near / (far - near)
        m[2, 3] = far * near / (far - near)
    else:
        m[2, 2] = far / (near - far)
        m[2, 3] = far * near / (near - far)
    return m


def orthographic(xmag: float, ymag: float, near: float, far: float) -> np.ndarray:
    """Right-handed orthographic projection with depth 0..1: view-space x in [-xmag, xmag] and y in [-ymag, ymag]
    fill the target whatever its aspect (glTF's orthographic camera), -z in [near, far] becomes depth 0..1."""
    if xmag <= 0 or ymag <= 0 or not (0 <= near < far < np.inf):
        raise ValueError(f"bad orthographic projection: xmag {xmag}, ymag {ymag}, near {near}, far {far}")
    m = np.eye(4)
    m[0, 0], m[1, 1] = 1.0 / xmag, 1.0 / ymag
    m[2, 2], m[2, 3] = 1.0 / (near - far), near / (near - far)
    return m


def look_at(eye, target, up=(0.0, 1.0, 0.0)) -> np.ndarray:
    """View matrix of a camera at ``eye`` looking at ``target`` (right-handed)."""
    eye, target, up = _as3(eye), _as3(target), _as3(up)
    forward = target - eye
    if np.linalg.norm(forward) == 0:
        raise ValueError("look_at: eye and target are the same point")
    forward /= np.linalg.norm(forward)
    side = np.cross(forward, up)
    if np.linalg.norm(side) < 1e-12:
        raise ValueError("look_at: the up vector is parallel to the view direction")
    side /= np.linalg.norm(side)
    true_up = np.cross(side, forward)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = side, true_up, -forward
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def translate(offset) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = _as3(offset)
    return m


def scale(factors) -> np.ndarray:
    f = np.broadcast_to(np.asarray(factors, dtype=np.float64), (3,))
    return np.diag([f[0], f[1], f[2], 1.0])


def rotate(axis, angle_rad: float) -> np.ndarray:
    """Rotation about ``axis`` by ``angle_rad`` (right-hand rule), Rodrigues' formula."""
    a = _as3(axis)
    a = a / np.linalg.norm(a)
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    m = np.eye(4)
    m[:3, :3] = np.eye(3) * c + s * k + (1 - c) * np.outer(a, a)
    return m


def normal_matrix(world: np.ndarray) -> np.ndarray:
    """The matrix that carries normals: the cofactor matrix of the world 3x3, sign-corrected.

    cof(M) = det(M) * inverse(M)^T, so it points normals the same way as the
    inverse-transpose when det > 0, and it needs no division, so it stays finite
    for near-singular scales such as 1e-6 on one axis (where the inverse blows up).
    For mirrors (det < 0) we multiply by the sign of det, so outward normals stay
    outward as they do with the inverse-transpose. Shaders normalise the result.
    """
    m = np.asarray(world, dtype=np.float64)[:3, :3]
    # row i of the cofactor matrix is the cross product of the other two rows (r1 x r2, r2 x r0, r0 x r1): the
    # same products and differences as the signed 2x2 minors, so the same bits, in one call (stage 3d calls
    # this per cube per frame: the 2x2-minor loop was most of its CPU time, issue 22)
    cof = np.cross(m[[1, 2, 0]], m[[2, 0, 1]])
    det = float(m[0] @ cof[0])
    return cof if det >= 0 else -cof


def determinants3(matrices: np.ndarray) -> np.ndarray:
    """det of each (..., 3+, 3+) matrix's upper 3x3, as row0 . (row1 x row2): one pass, no LU (np.linalg.det
    factorises each matrix; for a million world matrices that was most of a scene's load time, issue 31)."""
    m = np.asarray(matrices, dtype=np.float64)[..., :3, :3]
    return np.einsum("...i,...i->...", m[..., 0, :], np.cross(m[..., 1, :], m[..., 2, :]))


def flat(matrices: np.ndarray, tolerance: float = 1e-9) -> np.ndarray:
    """Whether each (..., 3+, 3+) matrix's upper 3x3 flattens space: |det| is at most ``tolerance`` times the
    product of its column lengths (the volume of the unit cube's image against that of a box with the same edge
    lengths: 1 for any rotation and scale, 0 for a zero scale or two parallel axes). Scale-free, so a model
    authored in micrometres (a node scale of 4e-6, det 6e-17: Khronos' quantized Avocado) is not flat."""
    m = np.asarray(matrices, dtype=np.float64)[..., :3, :3]
    edges = np.prod(np.linalg.norm(m, axis=-2), axis=-1)
    return np.abs(determinants3(m)) <= tolerance * edges


def to_gpu(matrix: np.ndarray) -> np.ndarray:
    """float32, column-major: what a WGSL mat4x4f / mat3x3f (after padding) expects.

    The transpose from numpy's row-major storage happens here and nowhere else.
    """
    return np.ascontiguousarray(np.asarray(matrix, dtype=np.float64).T, dtype=np.float32)
