"""Non-uniform, mirrored and near-singular scales: transformed normals stay correct and finite.

World = R @ diag(s) for a fixed rotation R. Analytic reference (float64): the inverse-transpose of R diag(s) is
R diag(1/s), so a unit normal n maps to normalize(R (n / s)) (numerics.normals.analytic_normals). Angle error =
atan2(|a x b|, a . b), over 518 normals (random + the six axis directions).

- CPU: transforms.normal_matrix (sign-corrected cofactor), float64: < 1e-12 rad for every scale (measured 3e-16).
- GPU compute probe (tests/numerics/shaders/numerics_normals.wgsl, float32), ours = numerics.normals.gpu_normal_matrix
  + safe_normalize: < 1e-6 rad and finite for every scale (measured 1.0e-7 rad on lavapipe).
- Counter-examples: the world matrix used for normals: ~90 degrees off for non-uniform scale; the cofactor without
  the sign correction: 180 degrees off for mirrors; the inverse-transpose computed in float32 on the GPU
  (cofactor / determinant): finite at s = 1e-6 (measured 1.0e-7 rad: it is not the problem there), NaN for every normal
  once the determinant underflows (s = 1e-20 on two axes, det = 1e-40).
- A lit, normal-mapped sphere squashed by (1, 1e-6, -1) rendered into rgba32float (64x64): every pixel finite and
  lit. (The NaN that plain normalize makes out of a zero vector in a render is shown in test_degenerate.py.)
"""

from __future__ import annotations

import numpy as np
import pytest
from numerics.gpu_eval import run_compute
from numerics.lit import interleave, render_lit
from numerics.normals import analytic_normals, gpu_normal_matrix

from wgpurender.core.models.tangents import vertex_tangents
from wgpurender.core.view import transforms as T

R = T.rotate((0.2, 1.0, 0.4), 0.9) @ T.rotate((1.0, 0.0, 0.0), 0.3)
SCALES = {
    "non-uniform": (2.0, 0.5, 3.0),
    "mirrored": (1.0, -1.0, 1.0),
    "near-singular+mirrored": (1.0, 1e-6, -1.0),
    "det-underflow": (1e-20, 1.0, 1e-20),
}


def _normals() -> np.ndarray:
    rng = np.random.default_rng(0)
    n = rng.normal(size=(512, 3))
    return np.concatenate([n / np.linalg.norm(n, axis=1, keepdims=True), np.eye(3), -np.eye(3)])


def angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle in radians between rows, accurate for tiny angles (unlike arccos)."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), (a * b).sum(axis=1))


def _gpu(ctx, world: np.ndarray, mode: int) -> np.ndarray:
    """Normals through the compute probe: MODE 0 ours, 1 float32 inverse-transpose, 2 world matrix."""
    n4 = np.eye(4)
    n4[:3, :3] = gpu_normal_matrix(world)
    normals = np.concatenate([_normals(), np.zeros((len(_normals()), 1))], axis=1).astype(np.float32)
    out = run_compute(
        ctx,
        "numerics_normals.wgsl",
        [normals, np.stack([T.to_gpu(world), T.to_gpu(n4)])],
        len(normals),
        constants={"MODE": mode},
        prelude=["numerics_safe.wgsl"],
    )
    return out[:, :3]


@pytest.mark.parametrize("name", SCALES)
def test_cpu_normal_matrix_matches_analytic(name):
    s = SCALES[name]
    n = _normals()
    got = (T.normal_matrix(R @ T.scale(s)) @ n.T).T
    assert np.isfinite(got).all()
    assert angle(got, analytic_normals(s, R, n)).max() < 1e-12


@pytest.mark.parametrize("name", SCALES)
def test_gpu_normals_finite_and_correct(ctx, name):
    s = SCALES[name]
    got = _gpu(ctx, R @ T.scale(s), mode=0)
    assert np.isfinite(got).all()
    assert angle(got, analytic_normals(s, R, _normals())).max() < 1e-6


def test_naive_world_matrix_for_normals_is_wrong(ctx):
    """Counter-example (MODE 2): normals carried by the world matrix itself."""
    for name in ("non-uniform", "near-singular+mirrored"):
        s = SCALES[name]
        assert angle(_gpu(ctx, R @ T.scale(s), mode=2), analytic_normals(s, R, _normals())).max() > np.radians(60)


def test_naive_cofactor_without_sign_flips_mirrored_normals():
    """Counter-example: cof(M) = det * M^-T points inward when det < 0."""
    s = SCALES["mirrored"]
    world = R @ T.scale(s)
    unsigned = np.linalg.det(world[:3, :3]) * np.linalg.inv(world[:3, :3]).T
    got = (unsigned @ _normals().T).T
    assert np.allclose(angle(got, analytic_normals(s, R, _normals())), np.pi, atol=1e-6)


def test_naive_float32_inverse_transpose(ctx):
    """Counter-example (MODE 1): finite at 1e-6, NaN everywhere once det underflows."""
    s = SCALES["near-singular+mirrored"]
    near = _gpu(ctx, R @ T.scale(s), mode=1)
    assert np.isfinite(near).all() and angle(near, analytic_normals(s, R, _normals())).max() < 1e-4
    assert np.isnan(_gpu(ctx, R @ T.scale(SCALES["det-underflow"]), mode=1)).all()


def uv_sphere(rings: int = 12, segments: int = 24):
    """Unit sphere: positions = normals, (u, v) in [0, 1], triangle indices."""
    v, u = np.meshgrid(np.linspace(0, 1, rings + 1), np.linspace(0, 1, segments + 1), indexing="ij")
    theta, phi = v * np.pi, u * 2 * np.pi
    p = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta), np.sin(theta) * np.sin(phi)], axis=-1).reshape(-1, 3)
    uv = np.stack([u, v], axis=-1).reshape(-1, 2)
    i = np.arange(rings)[:, None] * (segments + 1) + np.arange(segments)[None, :]
    quads = np.stack([i, i + segments + 1, i + 1, i + 1, i + segments + 1, i + segments + 2], axis=-1)
    return p, uv, quads.reshape(-1, 3)


def test_lit_squashed_sphere_is_finite(ctx):
    """A sphere squashed to a disk by (1, 1e-6, -1), seen face-on along y, lit and normal-mapped."""
    p, uv, idx = uv_sphere()
    tangents = vertex_tangents(p, p, uv, idx)
    world = T.scale(SCALES["near-singular+mirrored"])
    view = T.look_at((0.0, 3.0, 0.0), (0.0, 0.0, 0.0), up=(0.0, 0.0, 1.0))
    mvp = T.perspective(60, 1.0, 0.1, 10) @ view @ world
    image = render_lit(ctx, (64, 64), interleave(p, p, tangents, uv), idx, mvp, gpu_normal_matrix(world))
    covered = image[..., 3] > 0
    assert covered.sum() > 500  # the disk is really there (radius ~0.58 of the half-width: ~1060 px)
    assert np.isfinite(image).all()
    assert (image[covered, :3] > 0).all()
