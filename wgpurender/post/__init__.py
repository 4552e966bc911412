"""Post-processing effects: full-screen passes that read the previous image as a texture.

Public API:

- :data:`EFFECTS`: effect name -> class; :func:`effect_names`; :func:`create_effect`.
- :class:`PostEffect` (base), :class:`Param`, :class:`EffectDescription`.
- :class:`PostChain`: runs effects in order, ping-ponging between two textures.
- :func:`needs_shader_encoding`, :func:`encoding_of`: the sRGB rule (see post/srgb.py).

Each effect is one module here and one ``shaders_wgsl/post_<name>.wgsl``.
"""

from __future__ import annotations

from typing import Any

from ..errors import UserError
from .base import EffectDescription, Param, PostEffect, encoding_of, needs_shader_encoding
from .chain import PostChain, check_order, effects_for_target, intermediate_count
from .fxaa import Fxaa
from .grayscale import Grayscale
from .sepia import Sepia
from .sharpen import Sharpen
from .srgb import SrgbEncode
from .tonemap import ToneMap
from .vignette import Vignette

EFFECTS: dict[str, type[PostEffect]] = {
    cls.name: cls for cls in (ToneMap, Fxaa, Sharpen, Vignette, Grayscale, Sepia, SrgbEncode)
}


def effect_names() -> list[str]:
    return sorted(EFFECTS)


def create_effect(name: str, **params: Any) -> PostEffect:
    """An effect by name; UserError naming the valid effects or parameters otherwise."""
    if name not in EFFECTS:
        raise UserError(f"unknown post effect {name!r}: valid effects are {', '.join(effect_names())}")
    return EFFECTS[name](**params)


__all__ = [
    "EFFECTS",
    "EffectDescription",
    "Fxaa",
    "Grayscale",
    "Param",
    "PostChain",
    "PostEffect",
    "Sepia",
    "Sharpen",
    "SrgbEncode",
    "ToneMap",
    "Vignette",
    "check_order",
    "create_effect",
    "effect_names",
    "effects_for_target",
    "encoding_of",
    "intermediate_count",
    "needs_shader_encoding",
]
