"""Post effects as GPU-free specs: the one list of effects, their parameters and ranges, and the colour rule.

Both rendering paths read this module and nothing else to learn which effects exist:

- the scene file validates ``[[post]]`` entries with :func:`make_step` (unknown effect or parameter,
  a value out of range: one :class:`~wgpurender.core.errors.UserError`);
- the render plan (wgpurender/core/plan/) lists :class:`EffectStep` values (an effect, its validated
  parameters, and the scene key that asked for it) and groups them into passes;
- each path runs them with its own code: the wgpu path (wgpurender/wgpu_path/post/) generates its WGSL parameter
  structs from :attr:`EffectSpec.params` with wgpurender/core/shaders/uniforms.py; the raw path keeps its own GLSL
  and packers (wgpurender/raw_path/post/chain.py) but takes the effect list from the plan.

``reach`` is what decides fusion: a ``"pixel"`` effect reads only the pixel it writes (and its position),
so several of them compose as functions in one shader; a ``"neighbourhood"`` effect (FXAA, sharpen)
reads other pixels of its input, so its input must be a finished image in memory: it starts a new pass.

Colour encoding rule: float textures hold linear values; 8-bit textures hold sRGB-encoded values. The
``-srgb`` formats encode on write and decode on read in hardware; a plain 8-bit unorm target
(``rgba8unorm``, ``bgra8unorm``: some swapchains, and every 8-bit storage texture) needs the curve in a
shader, which is the ``srgb`` effect's job, always last in a chain.

This module imports no GPU API and no rendering path (the course core's rule).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from wgpurender.core.errors import UserError

PIXEL, NEIGHBOURHOOD = "pixel", "neighbourhood"

# 8-bit formats the hardware does not encode: a shader must apply the sRGB curve.
SHADER_ENCODED_FORMATS = frozenset({"rgba8unorm", "bgra8unorm"})
HARDWARE_ENCODED_FORMATS = frozenset({"rgba8unorm-srgb", "bgra8unorm-srgb"})


def needs_shader_encoding(fmt: str) -> bool:
    """True when writing linear values to ``fmt`` needs the sRGB curve applied in a shader."""
    return fmt in SHADER_ENCODED_FORMATS


def encoding_of(fmt: str) -> str:
    """Who encodes values written to ``fmt``: 'hardware', 'shader' or 'none' (linear float)."""
    if fmt in HARDWARE_ENCODED_FORMATS:
        return "hardware"
    if fmt in SHADER_ENCODED_FORMATS:
        return "shader"
    return "none"


@dataclass(frozen=True)
class Param:
    """One effect parameter: a float in [lo, hi], or a choice among names (packed as its index)."""

    name: str
    default: float | str
    doc: str
    lo: float = float("-inf")
    hi: float = float("inf")
    choices: tuple[str, ...] = ()

    @property
    def field(self) -> str:
        """The shader struct's field: the name, or ``<name>_index`` for a choice (it holds the choice's index)."""
        return f"{self.name}_index" if self.choices else self.name

    def validate(self, value: Any, effect: str) -> float | str:
        if self.choices:
            if not isinstance(value, str) or value not in self.choices:
                raise UserError(
                    f"post effect {effect!r}: {self.name} must be one of {', '.join(self.choices)}, got {value!r}"
                )
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise UserError(f"post effect {effect!r}: {self.name} must be a number, got {value!r}")
        if not (self.lo <= value <= self.hi):
            raise UserError(f"post effect {effect!r}: {self.name} must be in [{self.lo}, {self.hi}], got {value}")
        return float(value)

    def packed(self, value: float | str) -> float:
        """The number a shader reads: the value, or the index of the choice."""
        return float(self.choices.index(value)) if self.choices else float(value)

    def describe(self) -> str:
        if self.choices:
            return f"{self.name} = {'|'.join(self.choices)} (default {self.default!r}): {self.doc}"
        return f"{self.name} = number in [{self.lo}, {self.hi}] (default {self.default}): {self.doc}"


@dataclass(frozen=True)
class EffectSpec:
    """What an effect is, without any GPU: its name, parameters, reach, and what its input must allow."""

    name: str
    summary: str
    reach: str = PIXEL
    params: tuple[Param, ...] = ()
    filtering: bool = False  # samples its input bilinearly: the input must be a filterable format
    mask_format: str | None = None  # fragment path: a depth mask that skips flat blocks (FXAA, see post_fxaa.wgsl)

    @property
    def fusable(self) -> bool:
        return self.reach == PIXEL

    @property
    def struct_name(self) -> str:
        """The generated WGSL parameter struct's name, e.g. ``TonemapParams``."""
        return self.name.capitalize() + "Params"

    def param(self, name: str) -> Param:
        return next(p for p in self.params if p.name == name)

    def validate(self, params: Mapping[str, Any]) -> tuple[tuple[str, float | str], ...]:
        """Every parameter (defaults filled in) in declaration order; UserError for unknown ones or bad values."""
        known = {p.name: p for p in self.params}
        unknown = sorted(set(params) - set(known))
        if unknown:
            valid = ", ".join(known) or "none"
            raise UserError(f"post effect {self.name!r} has no parameter {unknown[0]!r}: valid parameters are {valid}")
        return tuple((p.name, p.validate(params.get(p.name, p.default), self.name)) for p in self.params)


@dataclass(frozen=True)
class EffectStep:
    """One effect of a chain as the plan lists it: validated parameters and the scene key that asked for it."""

    effect: str
    params: tuple[tuple[str, float | str], ...] = ()
    asked_by: str = ""

    @property
    def spec(self) -> EffectSpec:
        return EFFECTS[self.effect]

    @property
    def values(self) -> dict[str, float | str]:
        return dict(self.params)

    def packed(self) -> dict[str, float]:
        """Shader field -> number (choices as their index), for a generated parameter struct."""
        return {p.field: p.packed(v) for p, (_, v) in zip(self.spec.params, self.params, strict=True)}

    def label(self) -> str:
        args = ", ".join(f"{k}={v}" for k, v in self.params)
        return f"{self.effect}({args})"


EFFECTS: dict[str, EffectSpec] = {spec.name: spec for spec in (
    EffectSpec("tonemap", "HDR -> [0, 1]: exposure, then the ACES fitted curve (or Reinhard)", PIXEL, (
        Param("exposure", 1.0, "linear multiplier applied before the curve", lo=0.0, hi=1e4),
        Param("operator", "aces", "tone curve", choices=("aces", "reinhard")),
    )),
    EffectSpec("fxaa", "fast approximate anti-aliasing (FXAA 3.11-style, luma based)", NEIGHBOURHOOD, (
        Param("subpix", 0.75, "sub-pixel aliasing removal, 0 (off) .. 1 (softer)", lo=0.0, hi=1.0),
        Param("edge_threshold", 0.166, "minimum local contrast relative to the brightest neighbour", lo=0.0, hi=1.0),
        Param("edge_threshold_min", 0.0833, "minimum absolute local contrast (skips dark noise)", lo=0.0, hi=1.0),
    ), filtering=True, mask_format="depth16unorm"),
    EffectSpec("sharpen", "3x3 Laplacian sharpen with a strength", NEIGHBOURHOOD, (
        Param("strength", 0.5, "kernel weight k of each neighbour (0 = unchanged)", lo=0.0, hi=4.0),
    )),
    EffectSpec("vignette", "darken towards the corners", PIXEL, (
        Param("strength", 0.5, "how dark the corners get, 0 (none) .. 1 (black)", lo=0.0, hi=1.0),
        Param("radius", 0.5, "distance from the centre where darkening starts (corner = 1)", lo=0.0, hi=2.0),
        Param("softness", 0.5, "width of the transition", lo=1e-4, hi=2.0),
    )),
    EffectSpec("grayscale", "Rec. 709 luminance, mixed with the colour by amount", PIXEL, (
        Param("amount", 1.0, "0 = unchanged .. 1 = fully gray", lo=0.0, hi=1.0),
    )),
    EffectSpec("sepia", "classic sepia tone matrix, mixed with the colour by amount", PIXEL, (
        Param("amount", 1.0, "0 = unchanged .. 1 = full sepia", lo=0.0, hi=1.0),
    )),
    EffectSpec("srgb", "linear -> sRGB output encoding (in the shader only where the target format does not encode)"),
)}


def effect_names() -> list[str]:
    return sorted(EFFECTS)


def effect_spec(name: str) -> EffectSpec:
    """The spec of an effect; UserError naming the valid effects otherwise."""
    if name not in EFFECTS:
        raise UserError(f"unknown post effect {name!r}: valid effects are {', '.join(effect_names())}")
    return EFFECTS[name]


def make_step(name: str, asked_by: str = "", **params: Any) -> EffectStep:
    """A validated :class:`EffectStep`; UserError naming the valid effects or parameters otherwise."""
    return EffectStep(name, effect_spec(name).validate(params), asked_by)


def check_order(names: Sequence[str]) -> None:
    """The srgb effect may only be last: every later effect would take encoded values for linear ones."""
    for name in names[:-1]:
        if name == "srgb":
            raise UserError(
                f"post effect 'srgb' must be the last effect (chain: {', '.join(names)}): "
                "later effects expect linear values; move it to the end or remove it"
            )


def steps_for_target(steps: Sequence[EffectStep], target_format: str) -> list[EffectStep]:
    """The steps actually run for a target: a non-empty chain ending in a plain 8-bit target gets srgb appended."""
    steps = list(steps)
    if steps and needs_shader_encoding(target_format) and steps[-1].effect != "srgb":
        steps.append(EffectStep("srgb", (), f"render.output_format = {target_format} does not encode sRGB: "
                                            "an srgb step is appended"))
    return steps


def step_notes(step: EffectStep, input_format: str, output_format: str) -> tuple[str, ...]:
    """Format-dependent remarks for the plan (tone mapping of clipped input, who encodes sRGB)."""
    if step.effect == "tonemap" and not input_format.endswith("float"):
        return (f"input {input_format} is not HDR: values above 1 were already clipped",)
    if step.effect == "srgb":
        return {
            "hardware": (f"{output_format} encodes on write: the shader passes linear values through",),
            "shader": (f"{output_format} does not encode: the shader applies the sRGB curve",),
            "none": (f"{output_format} holds linear values: the shader copies",),
        }[encoding_of(output_format)]
    return ()


def group_passes(steps: Sequence[EffectStep], fuse: bool) -> list[tuple[EffectStep, ...]]:
    """Steps grouped into passes. Fused: a pass is an optional neighbourhood effect followed by every
    per-pixel effect after it (they only need the pixel it just computed); unfused: one pass per step."""
    if not fuse:
        return [(s,) for s in steps]
    groups: list[list[EffectStep]] = []
    for step in steps:
        if groups and step.spec.fusable:
            groups[-1].append(step)
        else:
            groups.append([step])
    return [tuple(g) for g in groups]
