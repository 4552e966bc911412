"""Grayscale: the Rec. 709 luma of the linear colour (0.2126 R + 0.7152 G + 0.0722 B)."""

from __future__ import annotations

from .base import Param, PostEffect


class Grayscale(PostEffect):
    name = "grayscale"
    summary = "Rec. 709 luminance, mixed with the colour by amount"
    shader = "post_grayscale.wgsl"
    params_spec = (Param("amount", 1.0, "0 = unchanged .. 1 = fully gray", lo=0.0, hi=1.0),)
