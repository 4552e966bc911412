"""The quality knobs of ``bench accuracy`` and how one setting of them becomes a renderer.

A :class:`Settings` is one point of the sweep: MSAA, supersampling factor, the scene (HDR) target format,
texture filtering for every material, and the depth setup. :func:`make_renderer` applies it:

- texture filtering replaces each material's sampler in the :class:`~wgpurender.core.scene.Scene` (so the plan
  builds mip chains exactly when the level uses them);
- MSAA, the render size, the scene target format, the depth format and reverse-Z are plan knobs, asked for
  through :meth:`~wgpurender.core.plan.RenderPlan.with_knobs` (``scene_format``, ``depth_format``, ``reverse_z``),
  so the renderer, which builds exactly what the plan lists, needs no arguments, and ``plan.explain()``
  stays true (reverse-Z: projection, compare "greater", clear 0, all from the plan).

WebGPU cannot multisample rgba32float (the format has no multisample capability in the spec), so a
setting with ``scene_format = "rgba32float"`` must have ``msaa = 1``: :meth:`Settings.problem` says so.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from wgpurender.core.errors import UserError
from wgpurender.core.scene import SamplerSettings, Scene

MSAA_LEVELS = (1, 4)
SS_LEVELS = (1, 2, 3, 4)
GROUND_TRUTH_SS = 8
FORMAT_LEVELS = ("rgba8unorm-srgb", "rgba16float", "rgba32float")
FILTER_LEVELS = ("nearest", "linear", "trilinear", "aniso4", "aniso16")
DEPTH_LEVELS = ("depth24plus", "depth32float", "reverse-z")
KNOBS = ("msaa", "ss", "format", "filter", "depth")  # the field each knob sets, in Settings order below

# filter level -> (filter, mipmaps, anisotropy); the material's address mode is kept.
FILTERS = {
    "nearest": ("nearest", False, 1),  # point sampling of the base level (no mips)
    "linear": ("linear", False, 1),  # bilinear, base level only
    "trilinear": ("linear", True, 1),  # bilinear within two mip levels, blended
    "aniso4": ("linear", True, 4),
    "aniso16": ("linear", True, 16),
}
# depth level -> (depth format, reverse_z)
DEPTHS = {"depth24plus": ("depth24plus", False), "depth32float": ("depth32float", False),
          "reverse-z": ("depth32float", True)}
NOT_MULTISAMPLED = ("rgba32float",)


@dataclass(frozen=True)
class Settings:
    """One quality setting. The defaults are the highest level of every knob at 1x supersampling."""

    msaa: int = 4
    ss: int = 1
    format: str = "rgba16float"
    filter: str = "aniso16"
    depth: str = "reverse-z"

    def label(self) -> str:
        return f"msaa{self.msaa} ss{self.ss} {self.format} {self.filter} {self.depth}"

    def with_(self, **changes) -> Settings:
        return dataclasses.replace(self, **changes)

    def problem(self) -> str | None:
        """Why this setting cannot be rendered, or None."""
        if self.format in NOT_MULTISAMPLED and self.msaa > 1:
            return f"{self.format} cannot be multisampled in WebGPU: use msaa 1 with it"
        if self.msaa not in MSAA_LEVELS:
            return f"msaa {self.msaa} is not one of {MSAA_LEVELS}"
        if self.format not in FORMAT_LEVELS or self.filter not in FILTERS or self.depth not in DEPTHS:
            return f"unknown level in {self.label()}"
        if self.ss < 1:
            return "supersampling factor must be at least 1"
        return None


# The highest level of every knob that can be combined: rgba16float because rgba32float cannot be multisampled
# (and at the 8-bit output float16's rounding, 2^-12 relative, is far below one step: docs/accuracy.md).
TOP = Settings()
GROUND_TRUTH = TOP.with_(ss=GROUND_TRUTH_SS)


def sampler_for(level: str, base: SamplerSettings) -> SamplerSettings:
    filt, mipmaps, anisotropy = FILTERS[level]
    return dataclasses.replace(base, filter=filt, mipmaps=mipmaps, anisotropy=anisotropy)


def with_filter(scene: Scene, level: str) -> Scene:
    """The scene with every material's sampler set to ``level`` (address modes kept)."""
    mats: dict[int, object] = {}

    def swap(material):
        if id(material) not in mats:
            mats[id(material)] = dataclasses.replace(material, sampler=sampler_for(level, material.sampler))
        return mats[id(material)]

    models = tuple(dataclasses.replace(m, material=swap(m.material)) for m in scene.models)
    materials = {name: swap(m) for name, m in scene.materials.items()}
    return dataclasses.replace(scene, models=models, materials=materials)


def make_renderer(ctx, scene: Scene, settings: Settings, base_size: tuple[int, int], *, knobs=KNOBS):
    """A SceneRenderer for ``settings`` at ``base_size * settings.ss``; knobs not in ``knobs`` keep the scene's own.

    The depth-stress scene, for instance, has no textures and no post chain: there only the depth knob applies.
    """
    from wgpurender.core.plan import resolve_plan
    from wgpurender.wgpu_path.scene import SceneRenderer

    problem = settings.problem()
    if problem:
        raise UserError(f"cannot render {settings.label()}: {problem}")
    if "filter" in knobs:
        scene = with_filter(scene, settings.filter)
    size = (base_size[0] * settings.ss, base_size[1] * settings.ss)
    # anisotropy "scene": the filter sweep sets each level's anisotropy itself, on every adapter
    plan = resolve_plan(scene, ctx.adapter_facts(), size=size, msaa=settings.msaa if "msaa" in knobs else None,
                        anisotropy="scene", **plan_knobs(settings, knobs))
    return SceneRenderer(ctx, scene, plan)


def plan_knobs(settings: Settings, knobs=KNOBS) -> dict:
    """The plan knobs (:meth:`wgpurender.core.plan.RenderPlan.with_knobs`) one setting asks for."""
    out: dict = {}
    if "format" in knobs:
        out["scene_format"] = settings.format
    if "depth" in knobs:
        out["depth_format"], out["reverse_z"] = DEPTHS[settings.depth]
    return out
