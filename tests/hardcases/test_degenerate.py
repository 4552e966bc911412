"""Degenerate geometry: zero-area triangles, zero-length normals and degenerate UVs put no NaN/inf in the image.

A 6x6-vertex grid (50 triangles) facing the camera, rendered lit and normal-mapped (numerics_lit.wgsl)
into rgba32float (64x64), where non-finite values are stored as they are instead of being clamped. Degenerate on
purpose: one row of vertices collapsed onto its neighbours (zero-area triangles), a 2x2 block of vertices with
zero-length normals (the triangles between them interpolate an exact zero normal), and a patch where all UVs are
equal (no tangent direction). Tangents come from wgpurender.core.models.tangents.vertex_tangents.

- ours (safe_normalize, SAFE = true): every pixel finite, tolerance 0 non-finite pixels; covered pixels lit (> 0).
- counter-example (plain WGSL normalize, SAFE = false): normalize(vec3(0)) = 0 * inverseSqrt(0) gives NaN pixels
  (121 of 3136 covered on lavapipe). The shader uses half-Lambert 0.5 + 0.5 n.l: a max(n.l, 0) would map NaN to 0
  on many GPUs and hide the NaN (not fix it).
- counter-example (tangents by the textbook formula, dividing by the UV determinant): inf/NaN on the degenerate
  UV patch, where vertex_tangents returns finite unit tangents (|t| = 1 within 1e-6, t . n = 0 within 1e-6).
"""

from __future__ import annotations

import numpy as np
import pytest
from numerics.lit import interleave, render_lit

from wgpurender.core.models.tangents import vertex_tangents
from wgpurender.core.view import transforms as T

N = 6  # vertices per side


def degenerate_grid():
    ys, xs = np.mgrid[0:N, 0:N] / (N - 1)
    positions = np.stack([xs * 2 - 1, ys * 2 - 1, np.zeros_like(xs)], axis=-1).reshape(-1, 3)
    positions[1 * N : 2 * N, 1] = positions[0:N, 1]  # row 1 collapsed onto row 0: zero-area triangles
    normals = np.tile([0.0, 0.0, 1.0], (N * N, 1))
    zero = [r * N + c for r in (3, 4) for c in (3, 4)]
    normals[zero] = 0.0  # the triangle pair between them has three zero normals
    uvs = np.stack([xs, 1 - ys], axis=-1).reshape(-1, 2)
    uvs[[r * N + c for r in (2, 3, 4) for c in (0, 1, 2)]] = (0.25, 0.25)  # degenerate UVs
    i = (np.arange(N - 1)[:, None] * N + np.arange(N - 1)[None, :]).reshape(-1)
    indices = np.stack([i, i + 1, i + N + 1, i, i + N + 1, i + N], axis=-1).reshape(-1, 3)
    return positions, normals, uvs, indices


def naive_tangents(positions, uvs, indices) -> np.ndarray:
    """Counter-example: per-face dP/du divided by the UV determinant, no guard."""
    p, uv = positions[indices], uvs[indices]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    d1, d2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        r = 1.0 / (d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1])
        return (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) * r[:, None]


def _render(ctx, safe: bool) -> np.ndarray:
    positions, normals, uvs, indices = degenerate_grid()
    tangents = vertex_tangents(positions, normals, uvs, indices)
    mvp = T.perspective(60, 1.0, 0.1, 10) @ T.look_at((0.0, 0.0, 2.0), (0.0, 0.0, 0.0))
    return render_lit(ctx, (64, 64), interleave(positions, normals, tangents, uvs), indices, mvp, np.eye(3), safe=safe)


def test_the_input_really_is_degenerate():
    positions, normals, uvs, indices = degenerate_grid()
    e1 = positions[indices[:, 1]] - positions[indices[:, 0]]
    e2 = positions[indices[:, 2]] - positions[indices[:, 0]]
    assert (np.linalg.norm(np.cross(e1, e2), axis=1) == 0).sum() >= 5
    assert (np.linalg.norm(normals[indices], axis=2) == 0).all(axis=1).any()
    assert not np.isfinite(naive_tangents(positions, uvs, indices)).all()


def test_vertex_tangents_stay_finite_and_unit():
    positions, normals, uvs, indices = degenerate_grid()
    t = vertex_tangents(positions, normals, uvs, indices)
    assert np.isfinite(t).all()
    assert np.allclose(np.linalg.norm(t[:, :3], axis=1), 1.0, atol=1e-6)
    assert np.abs((t[:, :3] * normals).sum(axis=1)).max() < 1e-6
    assert set(np.unique(t[:, 3])) <= {-1.0, 1.0}


def test_safe_shader_image_is_finite(ctx):
    image = _render(ctx, safe=True)
    assert np.isfinite(image).all()
    covered = image[..., 3] > 0
    assert covered.sum() > 1000
    assert (image[covered, :3] > 0).all()


def test_naive_normalize_puts_nan_in_the_image(ctx):
    """Counter-example: the same mesh with plain normalize."""
    image = _render(ctx, safe=False)
    assert np.isnan(image).any(axis=-1).sum() > 0


@pytest.mark.parametrize("v", [(0.0, 0.0, 0.0), (1e-30, 0.0, 0.0), (3e38, 3e38, 0.0), (np.inf, 0.0, 0.0)])
def test_safe_normalize_on_the_gpu(ctx, v):
    """Through the compute probe (MODE 0, identity normal matrix): finite, unit or the fallback (0, 0, 1).

    Tiny and huge finite vectors keep their direction (relative 1e-6); zero and inf give the fallback.
    """
    from numerics.gpu_eval import run_compute

    mats = np.stack([np.eye(4, dtype=np.float32)] * 2)
    out = run_compute(
        ctx,
        "numerics_normals.wgsl",
        [np.array([[*v, 0.0]], dtype=np.float32), mats],
        1,
        constants={"MODE": 0},
        prelude=["numerics_safe.wgsl"],
    )[0, :3]
    assert np.isfinite(out).all()
    vv = np.asarray(v, dtype=np.float64)
    expected = (
        vv / np.linalg.norm(vv / np.abs(vv).max()) / np.abs(vv).max() if np.isfinite(vv).all() and vv.any() else None
    )
    assert np.allclose(out, expected if expected is not None else (0.0, 0.0, 1.0), atol=1e-6)
