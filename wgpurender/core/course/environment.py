"""An environment for image-based lighting: a small equirectangular HDR made procedurally (a sky gradient, a dark
ground and a sun), and the mapping between its texels and directions that shaders_wgsl/ibl.wgsl uses too.

Equirectangular layout: column u in [0, 1) is the longitude phi = (u - 0.5) 2 pi, row v in [0, 1] the polar angle
theta = v pi from +y (row 0 is the zenith); direction (sin theta sin phi, cos theta, -sin theta cos phi), so u = 0.5
looks down -z. A texel is constant radiance over its patch of the sphere, of solid angle
(2 pi / w) (cos theta0 - cos theta1).
"""

from __future__ import annotations

import numpy as np

SUN_DIRECTION = (0.45, 0.55, -0.70)  # towards the sun (normalised in sky())
SUN_RADIUS_DEG = 6.0
SUN_RADIANCE = (40.0, 36.0, 30.0)
ZENITH, HORIZON, GROUND = (0.25, 0.45, 0.9), (0.9, 0.85, 0.8), (0.12, 0.1, 0.08)


def directions(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Unit directions (..., 3) of equirectangular coordinates u, v in [0, 1]."""
    phi, theta = (np.asarray(u, np.float64) - 0.5) * 2 * np.pi, np.asarray(v, np.float64) * np.pi
    return np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], axis=-1)


def texel_directions(width: int, height: int, sub: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Directions (height * sub, width * sub, 3) of a sub x sub grid inside each texel, and each one's solid angle."""
    u = (np.arange(width * sub) + 0.5) / (width * sub)
    v_edges = np.arange(height * sub + 1) / (height * sub)
    v = (v_edges[:-1] + v_edges[1:]) / 2
    uu, vv = np.meshgrid(u, v)
    band = (2 * np.pi / (width * sub)) * (np.cos(v_edges[:-1] * np.pi) - np.cos(v_edges[1:] * np.pi))
    return directions(uu, vv), np.broadcast_to(band[:, None], uu.shape)


def sky(width: int = 128, height: int = 64) -> np.ndarray:
    """(height, width, 3) float32 linear radiance: a gradient from the horizon to the zenith, a dark ground below,
    a sun disc of SUN_RADIUS_DEG (each texel its value at its centre)."""
    d, _ = texel_directions(width, height)
    up = d[..., 1:2]
    t = np.sqrt(np.clip(up, 0.0, 1.0))
    out = np.where(up >= 0, (1 - t) * np.asarray(HORIZON) + t * np.asarray(ZENITH), np.asarray(GROUND))
    sun = np.asarray(SUN_DIRECTION) / np.linalg.norm(SUN_DIRECTION)
    out = np.where((d @ sun >= np.cos(np.radians(SUN_RADIUS_DEG)))[..., None], np.asarray(SUN_RADIANCE), out)
    return out.astype(np.float32)
