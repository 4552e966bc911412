"""The final scene on the raw-Vulkan path: a scene file drawn the course's way, to compare with wgpu's.

One render pass with two subpasses: subpass 0 draws the models into the 4x MSAA HDR attachment
(rgba16float) with a resolve attachment and an MSAA depth attachment; subpass 1 reads the resolved
image as an input attachment (subpassLoad) and applies the post chain's per-pixel effects in one
fragment shader. Effects that read neighbouring pixels (fxaa, sharpen) cannot read through an input
attachment: each runs in a render pass of its own that samples the previous result after an image
barrier, followed by the per-pixel effects after it in that pass's subpass 1 (neighbourhood.py).

Public API: :func:`render_scene_reference` ``(path, size=None, fmt=None, msaa=None, t=0.0) ->
pixels``; :func:`render_scene_plan` ``(plan) -> pixels`` (a plan that
:func:`wgpurender.core.plan.resolve_plan` resolved for ``get_vulkan().adapter_facts()``);
:func:`unsupported` ``(plan) -> [reasons]``.

Modules, one idea each, like wgpurender/wgpu_path/scene/: ``support`` (what can be drawn),
``uniforms`` (std140 blocks and push constants, offsets by hand), ``variants`` (a plan's shader
variant as glslc -D flags), ``resources`` (meshes, textures, samplers), ``renderpass`` (attachments,
the two subpasses, dependencies), ``scene_subpass`` (descriptor sets, pipelines per variant, the
draws), ``post`` (the post subpass), ``neighbourhood`` (fxaa and sharpen passes),
``frame`` (a whole frame and the readback).
"""

from wgpurender.raw_path.scene.frame import render_scene_plan, render_scene_reference
from wgpurender.raw_path.scene.support import unsupported

__all__ = ["render_scene_plan", "render_scene_reference", "unsupported"]
