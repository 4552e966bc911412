"""The one light rig both renderers get: a white directional light from the upper left front and a dim
ambient, over a grey background (linear 0.05, sRGB ~0.25)."""

from __future__ import annotations

import numpy as np

LIGHT_DIRECTION = (0.4, -0.5, -0.77)  # the direction the light travels (world space)
BACKGROUND_LINEAR = (0.05, 0.05, 0.05)
BACKGROUND_SRGB = (0.247, 0.247, 0.247, 1.0)


def scene_lights() -> str:
    return f'[[lights]]\ntype = "directional"\ndirection = {list(LIGHT_DIRECTION)}\nintensity = 1.0\n'


def pygfx_lights(target: np.ndarray, direction) -> list:
    import pygfx as gfx

    d = np.array(direction, np.float64)
    sun = gfx.DirectionalLight("#ffffff", intensity=3.0)
    sun.local.position = (target - d / np.linalg.norm(d) * 10).tolist()
    sun.target.local.position = target.tolist()
    return [sun, gfx.AmbientLight("#ffffff", intensity=0.3)]
