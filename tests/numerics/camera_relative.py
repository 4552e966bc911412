"""Camera-relative transforms: compose in float64 so float32 never holds a coordinate of 1e6.

A float32 has 24 bits of mantissa: at 1e6 its spacing is 0.0625, so a vertex placed in world space a million
units from the origin (the course's naive ``proj * view * model * p`` with model and view in separate float32
uniforms) snaps to a 6 cm grid *before* the view transform subtracts the camera position again. Seen from a few
metres away that is several pixels, and as the camera moves the vertices jump between grid points (jitter).

Two fixes, both doing the large subtraction in float64 on the CPU:

- :func:`model_view`: upload ``view @ world`` (float64 product) instead of ``world`` and ``view`` apart. The
  translation cancels in float64; the float32 matrix has small entries.
- :func:`camera_relative`: keep a world-like space for lighting, but centred on the camera: world' = T(-eye)
  @ world, view' = the view's rotation alone. Then ``view' @ world' == view @ world`` exactly in real arithmetic.
"""

from __future__ import annotations

import numpy as np


def model_view(view: np.ndarray, world: np.ndarray) -> np.ndarray:
    """``view @ world`` in float64 (give the result to transforms.to_gpu)."""
    return np.asarray(view, dtype=np.float64) @ np.asarray(world, dtype=np.float64)


def eye_position(view: np.ndarray) -> np.ndarray:
    """The camera position of a rigid view matrix [R | -R eye]: eye = -R^T t (float64)."""
    v = np.asarray(view, dtype=np.float64)
    return -v[:3, :3].T @ v[:3, 3]


def camera_relative(world: np.ndarray, view: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(world', view') with the camera at the origin of world': world' = T(-eye) @ world, view' = rotation of view.

    view' @ world' equals view @ world; both factors have small translations when the object is near the camera.
    """
    view = np.asarray(view, dtype=np.float64)
    world_rel = np.asarray(world, dtype=np.float64).copy()
    world_rel[:3, 3] -= eye_position(view)
    view_rot = np.eye(4)
    view_rot[:3, :3] = view[:3, :3]
    return world_rel, view_rot
