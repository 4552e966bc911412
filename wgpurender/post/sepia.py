"""Sepia: the classic sepia tone matrix (rows 0.393 0.769 0.189 / 0.349 0.686 0.168 / 0.272 0.534 0.131)."""

from __future__ import annotations

from .base import Param, PostEffect


class Sepia(PostEffect):
    name = "sepia"
    summary = "classic sepia tone matrix, mixed with the colour by amount"
    shader = "post_sepia.wgsl"
    params_spec = (Param("amount", 1.0, "0 = unchanged .. 1 = full sepia", lo=0.0, hi=1.0),)
