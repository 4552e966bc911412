"""FXAA: luma-based post-process anti-aliasing, in the style of FXAA 3.11 (quality).

The algorithm is explained step by step in shaders_wgsl/post_fxaa.wgsl. It needs
bilinear filtering of its input (the edge search samples between pixels), so the
input must be a filterable format: rgba16float or 8-bit, not rgba32float.
"""

from __future__ import annotations

from .base import Param, PostEffect


class Fxaa(PostEffect):
    name = "fxaa"
    summary = "fast approximate anti-aliasing (FXAA 3.11-style, luma based)"
    shader = "post_fxaa.wgsl"
    filtering = True
    params_spec = (
        Param("subpix", 0.75, "sub-pixel aliasing removal, 0 (off) .. 1 (softer)", lo=0.0, hi=1.0),
        Param("edge_threshold", 0.166, "minimum local contrast relative to the brightest neighbour", lo=0.0, hi=1.0),
        Param("edge_threshold_min", 0.0833, "minimum absolute local contrast (skips dark noise)", lo=0.0, hi=1.0),
    )
