"""The render plan: what a scene needs on the GPU, derived from the scene and nothing else.

:func:`resolve_plan` turns a :class:`~wgpurender.core.scene.Scene` into pure data (no GPU
objects): attachments with formats and sample counts, passes in order, shader
variants and pipelines, textures and samplers. The scene renderer builds exactly
these; everything a scene does not use is left out:

- a shader variant is the frozen set of features one material needs
  (``albedo_map``, ``normal_map``, ``roughness_map``, ``lighting``, ``flip_v``,
  ``srgb_output``, and light counts ``directional_lights:N`` / ``point_lights:N``);
  no ``normal_map`` feature and no tangent attribute unless a lit material has a
  normal map; no lighting code (and no normal attribute) for unlit materials, nor for
  lit ones in a scene without lights (only ambient x albedo remains: the unlit variant
  draws it with the base colour scaled by the ambient);
- no multisampled attachment and no resolve at ``msaa = 1``, nor without models: a
  camera-only scene's pass only clears (no depth, pipeline, buffer or bind group);
- no post pass at all when the chain is empty: the scene draws into the output;
- no HDR (rgba16float) image unless ``hdr = true`` or the chain tone-maps.

Every item carries the reason it is there (which scene key asked for it), ``plan.absent``
what was left out and why, ``plan.objects`` every object the wgpu renderer creates, and
:meth:`RenderPlan.explain` prints them. Modules: :mod:`.model` (the dataclasses), :mod:`.build`
(scene -> plan, section by section: knobs, then :mod:`.targets` (scene image, MSAA, depth, output),
:mod:`.draws` (per model: material variant, pipeline, draw), :mod:`.textures` (textures and samplers),
:mod:`.post` (the post chain: fusion, path, bytes)), :mod:`.objects` (every GPU object, with why),
:mod:`.explain` (the text), :mod:`.resolve` (:func:`resolve_plan`: the one function every entry point draws
its plan from, the knobs decided per adapter). ``python -m wgpurender.core.plan SCENE.toml`` prints a plan;
:func:`explain_scene` is what ``render --explain`` and the API's ``explain`` call.

Variant flags are plain identifiers so a template can test them with
``#if normal_map`` (wgpurender/core/shaders/shader_variants.py); the light counts are separate
numbers (``ShaderVariant.counts``) for array sizes.
"""

from wgpurender.core.plan.build import material_variant
from wgpurender.core.plan.model import *  # noqa: F403  (every dataclass and constant of the plan)
from wgpurender.core.plan.model import __all__ as _model_names
from wgpurender.core.plan.objects import GpuObject
from wgpurender.core.plan.post import plan_post_passes
from wgpurender.core.plan.resolve import KNOB_FLAGS, explain_scene, main, resolve_knobs, resolve_plan

__all__ = [*_model_names, "KNOB_FLAGS", "GpuObject", "explain_scene", "main", "material_variant", "plan_post_passes",
           "resolve_knobs", "resolve_plan"]
