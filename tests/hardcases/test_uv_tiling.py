"""Huge UV tiling: the far end of a 1e4-repeat tiling, sampled against the exact float64 texture lookup.

A viewport-filling quad (128x32) whose UVs run from (9998.12, 9999.31) about 1.73 repeats across and 0.41 down
(a slightly skewed parallelogram, so pixel centres hit every sub-texel phase), on a 256x256 texture that stores
its own texel indices, nearest filtering, repeat addressing. Reference, float64: the UV at each pixel centre (affine
over the quad), texel coordinate fract(uv) * 256, texel index = its floor.

- naive (raw UVs ~1e4 as float32 vertex attributes): float32 spacing at 1e4 is 2^-10 of a repeat = 0.25 texel;
  the interpolated texel coordinate is off by up to 0.40 texel and about a third of the pixels fetch the wrong
  texel (measured 0.402 / 1365 of 4096 on lavapipe). Required: > 0.1 texel and > 10% wrong.
- ours (numerics.uv_tiling.wrap_uvs: the mesh's UVs shifted by an integer in float64 first): texel coordinate error
  < 0.01 texel (measured 5e-5) and no wrong fetch at pixels more than 0.02 texel from a texel edge (tolerance 0;
  nearer than that the sampler's own sub-texel rounding may decide).
"""

from __future__ import annotations

import numpy as np
import pytest
from numerics.uv_tiling import exact_uvs, render_uv_probe, wrap_uvs

SIZE = (128, 32)
TEX = 256
U0, V0 = 9998.123456789, 9999.3141592
# top-left, top-right, bottom-left, bottom-right: a parallelogram, so the quad's interpolation is affine
CORNERS = np.array([[U0, V0], [U0 + 1.7316, V0 + 0.01], [U0 + 0.003, V0 + 0.4137], [U0 + 1.7346, V0 + 0.4237]])


@pytest.fixture(scope="module")
def reference():
    uv = exact_uvs(SIZE, CORNERS)
    texel = (uv - np.floor(uv)) * TEX
    edge_distance = np.abs(texel - np.round(texel)).min(axis=-1)
    return texel, np.floor(texel), edge_distance


def _errors(ctx, corner_uvs, reference):
    texel, index, edge_distance = reference
    image = render_uv_probe(ctx, SIZE, corner_uvs, TEX).astype(np.float64)
    err = np.abs(image[..., :2] - texel)
    err = np.minimum(err, TEX - err)  # 255.99 vs 0.01 is a wrap, not an error of 256
    wrong = (image[..., 2:] != index).any(axis=-1)
    return err.max(), wrong, edge_distance


def test_wrapped_uvs_sample_the_exact_texel(ctx, reference):
    uvs = wrap_uvs(CORNERS)
    assert np.abs(uvs).max() < 3 and uvs.dtype == np.float32
    assert np.allclose(np.diff(uvs, axis=0), np.diff(CORNERS, axis=0), atol=1e-6)  # differences kept
    max_err, wrong, edge_distance = _errors(ctx, uvs, reference)
    assert max_err < 0.01
    assert not wrong[edge_distance > 0.02].any()


def test_naive_large_uvs_lose_subtexel_precision(ctx, reference):
    """Counter-example: the same quad with its raw float32 UVs."""
    max_err, wrong, _ = _errors(ctx, CORNERS.astype(np.float32), reference)
    assert max_err > 0.1
    assert wrong.mean() > 0.1
