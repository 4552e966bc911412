"""Tone mapping: linear HDR in, linear [0, 1] out, with an exposure multiplier.

Default curve: ACES fitted (Stephen Hill's fit of the ACES reference rendering
transform + sRGB output transform). Chosen over Reinhard because it has a toe and
a shoulder like film: midtones keep their contrast, highlights roll off smoothly
and desaturate towards white instead of clipping to a saturated hue, and it
reaches 1.0 at a finite input (Reinhard never does, so its whites look grey and
the whole image flat). Reinhard (c / (1 + c) per channel) stays available as
``operator = "reinhard"`` for comparison.
"""

from __future__ import annotations

from .base import Param, PostEffect


class ToneMap(PostEffect):
    name = "tonemap"
    summary = "HDR -> [0, 1]: exposure, then the ACES fitted curve (or Reinhard)"
    shader = "post_tonemap.wgsl"
    params_spec = (
        Param("exposure", 1.0, "linear multiplier applied before the curve", lo=0.0, hi=1e4),
        Param("operator", "aces", "tone curve", choices=("aces", "reinhard")),
    )

    def notes(self, input_format: str, output_format: str) -> tuple[str, ...]:
        if not input_format.endswith("float"):
            return (f"input {input_format} is not HDR: values above 1 were already clipped",)
        return ()
