"""Vignette: darken the image towards its corners.

d is the distance of the pixel centre from the image centre in uv units, scaled
so a corner is 1; the colour is multiplied by
``1 - strength * smoothstep(radius, radius + softness, d)``.
"""

from __future__ import annotations

from .base import Param, PostEffect


class Vignette(PostEffect):
    name = "vignette"
    summary = "darken towards the corners"
    shader = "post_vignette.wgsl"
    params_spec = (
        Param("strength", 0.5, "how dark the corners get, 0 (none) .. 1 (black)", lo=0.0, hi=1.0),
        Param("radius", 0.5, "distance from the centre where darkening starts (corner = 1)", lo=0.0, hi=2.0),
        Param("softness", 0.5, "width of the transition", lo=1e-4, hi=2.0),
    )
