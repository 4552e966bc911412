"""Subpass 1: the post chain's per-pixel effects in ONE fragment shader reading an input attachment.

Why one subpass for the whole chain, not one per effect: every effect the raw path can run is a
function of one pixel (and its position), so the chain composes as functions in registers; one
subpass per effect would add an attachment per step (a colour attachment in subpass i, the input
of subpass i + 1), a dependency per step, and a write and read of the whole image per step, which
is exactly the memory traffic subpasses exist to avoid. The price: between effects the colour
stays float32, where the wgpu path stores it in its rgba16float ping-pong textures (see
tests/test_vulkan_ref_scene.py for what that changes: ``wgpu_intermediates`` sets the
F16_BETWEEN_STEPS flag of shaders_glsl/post_chain.frag, which rounds like the wgpu path's
rgba16float intermediates, to show that this is the whole difference; with hdr = false the
intermediates are 8-bit sRGB, whose encoding on lavapipe is an approximation that no shader
formula reproduces bit for bit, so the flag does nothing there).

The effect list and parameters come from the plan (``plan.post_steps``: the GPU-free steps of
wgpurender/core/course/effects.py, whatever passes the wgpu path groups them into); the kind numbers and
the packing below are this path's own, so a parameter the two paths read differently shows up as an
image difference in the cross-check. The chain is data: a uniform block (descriptor set 0, binding 1)
lists the steps' kinds and parameters (uniforms.pack_chain); binding 0 is the INPUT_ATTACHMENT
descriptor of the resolved scene image, in SHADER_READ_ONLY_OPTIMAL, written with vkUpdateDescriptorSets.
"""

from __future__ import annotations

from collections.abc import Sequence
from contextlib import ExitStack

import vulkan as vk

from wgpurender.core.course.effects import PIXEL, EffectStep, needs_shader_encoding
from wgpurender.core.plan import RenderPlan
from wgpurender.raw_path.device import descriptors
from wgpurender.raw_path.device import uniforms as U
from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.images import Image
from wgpurender.raw_path.device.memory import HOST_MEMORY, create_buffer, write_host_buffer
from wgpurender.raw_path.device.pipeline import PipelineDesc, create_pipeline, create_pipeline_layout
from wgpurender.raw_path.device.renderpass import RenderPass

FRAGMENT = vk.VK_SHADER_STAGE_FRAGMENT_BIT
GRAPHICS = vk.VK_PIPELINE_BIND_POINT_GRAPHICS
# effect -> the kind number of shaders_glsl/post_chain.frag (its #defines); every per-pixel effect of the specs
STEP_KINDS = {"tonemap": 0, "vignette": 1, "grayscale": 2, "sepia": 3, "srgb": 4}
TONE_CURVES = {"aces": 0.0, "reinhard": 1.0}


def step_params(step: EffectStep, output_format: str) -> tuple[float, ...]:
    """The parameters in the order post_chain.frag reads them (p0, p1, p2): this path's own packing."""
    params = step.values
    if step.effect == "tonemap":
        return float(params["exposure"]), TONE_CURVES[params["operator"]]
    if step.effect == "srgb":  # the curve only where the output does not encode by itself
        return (1.0 if needs_shader_encoding(output_format) else 0.0,)
    if step.effect in STEP_KINDS and step.spec.reach == PIXEL:  # vignette, grayscale, sepia: in spec order
        return tuple(float(params[p.name]) for p in step.spec.params)
    raise ValueError(f"no post_chain.frag step for {step.effect!r}")  # support.check_supported refuses it first


def chain_steps(plan: RenderPlan, steps: Sequence[EffectStep] | None = None) -> list[tuple[int, tuple[float, ...]]]:
    """The steps (default: the plan's whole chain, ``plan.post_steps``) for the chain's uniform block."""
    steps = plan.post_steps if steps is None else steps
    return [(STEP_KINDS[s.effect], step_params(s, plan.output_format)) for s in steps]


class PostSubpass:
    """The input attachment descriptor, the chain's UBO and the full-screen pipeline of subpass 1."""

    def __init__(self, ctx: VulkanContext, owned: ExitStack, plan: RenderPlan, render_pass: RenderPass,
                 scene_image: Image, wgpu_intermediates: bool = False, passes: Sequence[EffectStep] | None = None,
                 subpass: int = 1) -> None:
        """``passes``: the per-pixel effects this subpass runs (default: the whole chain; a neighbourhood
        pass runs the effects after its own, neighbourhood.py); ``subpass``: its index in ``render_pass``."""
        self.ctx, self.plan, self.passes = ctx, plan, passes
        bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT, FRAGMENT),
                    descriptors.binding(1, vk.VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, FRAGMENT)]
        set_layout = descriptors.create_set_layout(ctx, owned, bindings)
        pool = descriptors.create_pool(ctx, owned, [bindings])
        (self.set,) = descriptors.allocate_sets(ctx, pool, [set_layout])
        self.buffer = create_buffer(ctx, owned, U.CHAIN_SIZE, vk.VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, HOST_MEMORY)
        descriptors.update(ctx, [
            descriptors.write_image(self.set, 0, scene_image.view, vk.VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                    vk.VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT),
            descriptors.write_buffer(self.set, 1, self.buffer.handle, 0, U.CHAIN_SIZE),
        ])
        self.layout = create_pipeline_layout(ctx, owned, [set_layout])
        defines = (f"MAX_POST_STEPS={U.MAX_POST_STEPS}",)
        if wgpu_intermediates and scene_image.format == "rgba16float":
            defines += ("F16_BETWEEN_STEPS",)
        desc = PipelineDesc("fullscreen.vert", "post_chain.frag", subpass=subpass, defines=defines)
        self.pipeline = create_pipeline(ctx, owned, desc, self.layout, render_pass)

    def record(self, cmd, size: tuple[int, int]) -> None:
        """Write the chain's UBO (host write before the submit) and draw the full-screen triangle."""
        write_host_buffer(self.ctx, self.buffer, U.pack_chain(size, chain_steps(self.plan, self.passes)))
        vk.vkCmdBindPipeline(cmd, GRAPHICS, self.pipeline)
        vk.vkCmdBindDescriptorSets(cmd, GRAPHICS, self.layout, 0, 1, [self.set], 0, None)
        vk.vkCmdDraw(cmd, 3, 1, 0, 0)
