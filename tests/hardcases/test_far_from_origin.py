"""A model 1e6 units from the origin, the camera a few units beside it: no vertex jitter with camera-relative math.

The GPU computes clip positions in float32 exactly as a vertex shader would (compute probe
numerics_transform.wgsl: clip = second * (first * p)); the reference is the same product in float64
on the same float32 model-space vertices. Error = max screen-space distance in pixels on a 256x256 viewport,
over 8 camera positions 1 mm apart (a slow camera move: where jitter shows).

- naive (world and proj*view uploaded as separate float32 matrices): the world-space vertex is rounded to the
  float32 grid at 1e6 (spacing 0.0625) -> errors of several pixels (measured 5.7..10.1 px on lavapipe); must be > 1 px.
- camera-relative (view*world composed in float64, or world' = T(-eye) world with a rotation-only view):
  must be < 0.01 px (measured 2e-5 px).
"""

from __future__ import annotations

import numpy as np
import pytest
from numerics.camera_relative import camera_relative, eye_position, model_view
from numerics.gpu_eval import run_compute

from wgpurender.core.view import transforms as T

SIZE = (256, 256)
ORIGIN = np.array([1e6, 12.3, -1e6 + 0.37])
WORLD = T.translate(ORIGIN) @ T.rotate((0, 1, 0), 0.7)
PROJ = T.perspective(60, SIZE[0] / SIZE[1], 0.1, 100)
TOLERANCE_PX = 0.01


def _vertices() -> np.ndarray:
    rng = np.random.default_rng(1)
    p = np.concatenate([rng.uniform(-0.5, 0.5, (256, 3)), np.ones((256, 1))], axis=1)
    return p.astype(np.float32)


def _pixels(clip: np.ndarray) -> np.ndarray:
    clip = np.asarray(clip, dtype=np.float64)
    ndc = clip[:, :2] / clip[:, 3:4]
    return np.stack([(ndc[:, 0] + 1) * 0.5 * SIZE[0], (1 - ndc[:, 1]) * 0.5 * SIZE[1]], axis=1)


def _views():
    return [T.look_at(ORIGIN + np.array([3.0 + 1e-3 * k, 1.0, 2.0]), ORIGIN) for k in range(8)]


def _max_error(ctx, split) -> float:
    """Largest pixel error over the camera path; ``split(view) -> (first, second)`` float64 matrices."""
    p = _vertices()
    worst = 0.0
    for view in _views():
        reference = _pixels((PROJ @ view @ WORLD @ p.astype(np.float64).T).T)
        first, second = split(view)
        clip = run_compute(ctx, "numerics_transform.wgsl", [p, np.stack([T.to_gpu(first), T.to_gpu(second)])], len(p))
        assert np.isfinite(clip).all()
        worst = max(worst, float(np.abs(_pixels(clip) - reference).max()))
    return worst


def test_naive_float32_world_then_view_jitters(ctx):
    """Counter-example: world and proj*view as separate float32 matrices: multi-pixel error."""
    assert _max_error(ctx, lambda view: (WORLD, PROJ @ view)) > 1.0


def test_model_view_composed_in_float64(ctx):
    assert _max_error(ctx, lambda view: (model_view(view, WORLD), PROJ)) < TOLERANCE_PX


def test_camera_relative_world(ctx):
    def split(view):
        world_rel, view_rot = camera_relative(WORLD, view)
        assert np.abs(world_rel[:3, 3]).max() < 10  # nothing large reaches float32
        return world_rel, PROJ @ view_rot

    assert _max_error(ctx, split) < TOLERANCE_PX


@pytest.mark.parametrize("eye", [(1e6, 2.0, -3.0), (-4e6, 1e5, 7.5)])
def test_camera_relative_is_the_same_transform(eye):
    """view' @ world' == view @ world (float64, relative 1e-12) and eye_position inverts look_at."""
    view = T.look_at(eye, np.asarray(eye) + np.array([1.0, 0.2, -0.5]))
    assert np.allclose(eye_position(view), eye, rtol=1e-12, atol=1e-9)
    world_rel, view_rot = camera_relative(WORLD, view)
    assert np.allclose(view_rot @ world_rel, view @ WORLD, rtol=1e-12, atol=1e-9)
