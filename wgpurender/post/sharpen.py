"""Sharpen: a 3x3 Laplacian kernel, ``c * (1 + 4k) - k * (n + s + w + e)``.

This is an unsharp mask whose blur is the 4-neighbour average (k = strength / 4
of the classic form). Borders clamp to the edge; results are clamped at 0 so a
dark pixel beside a bright one cannot go negative in an HDR chain.
"""

from __future__ import annotations

from .base import Param, PostEffect


class Sharpen(PostEffect):
    name = "sharpen"
    summary = "3x3 Laplacian sharpen with a strength"
    shader = "post_sharpen.wgsl"
    params_spec = (Param("strength", 0.5, "kernel weight k of each neighbour (0 = unchanged)", lo=0.0, hi=4.0),)
