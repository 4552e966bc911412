"""The wgpu path's post runners: a plan's post passes as fragment or compute shaders.

What an effect *is* (name, parameters with ranges, reach) lives in the API-free course core,
:mod:`wgpurender.core.course.effects`; which passes run, fused or not, on which path, is the plan's
(:mod:`wgpurender.core.plan`). This package only runs them:

- :mod:`.shaders`: the WGSL of a pass, generated (parameter structs from the specs, the effects composed);
- :mod:`.passes`: the two small runners, :class:`FragmentPass` and :class:`ComputePass`;
- :mod:`.chain`: :class:`PostRunner` (a plan's passes) and :class:`PostChain` (a bare list of steps);
- :mod:`.tiles`: FXAA's reads through a workgroup tile (the plan's pass that recomputes the effects before
  FXAA; for a stored image a benchmark variant). The FXAA variants the plan never draws (the edge list, the
  luma in alpha) live with the benchmarks that time them, in wgpurender/bench/fxaa_variants/.

Each effect is one ``shaders_wgsl/post_<name>.wgsl`` holding functions, not entry points.
"""

from __future__ import annotations

from typing import Any

from wgpurender.core.course.effects import (
    EFFECTS,
    EffectSpec,
    EffectStep,
    Param,
    check_order,
    effect_names,
    encoding_of,
    make_step,
    needs_shader_encoding,
    steps_for_target,
)
from wgpurender.wgpu_path.post.chain import PostChain, PostRunner, attachment_usage, output_usage
from wgpurender.wgpu_path.post.passes import ComputePass, FragmentPass


def create_effect(name: str, **params: Any) -> EffectStep:
    """A validated effect step by name (GPU-free); UserError naming the valid effects or parameters otherwise."""
    return make_step(name, "", **params)


__all__ = [
    "EFFECTS",
    "ComputePass",
    "EffectSpec",
    "EffectStep",
    "FragmentPass",
    "Param",
    "PostChain",
    "PostRunner",
    "attachment_usage",
    "check_order",
    "create_effect",
    "effect_names",
    "encoding_of",
    "make_step",
    "needs_shader_encoding",
    "output_usage",
    "steps_for_target",
]
