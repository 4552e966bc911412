"""Neighbourhood effects (fxaa, sharpen) on the raw path: a render pass of their own that samples the previous result.

An input attachment gives a fragment only the pixel under it (``subpassLoad`` takes no coordinates),
so an effect that reads neighbouring pixels cannot be a subpass of the scene's pass. The chain is
cut before each such effect (:func:`split_chain`):

- the scene's pass runs the per-pixel effects before the first cut in its subpass 1 (the *head*)
  and ends in a stored ``handoff`` image (renderpass.py);
- each neighbourhood effect is one :class:`NeighbourhoodPass`: an explicit image memory barrier
  (the course's layout transition with availability and visibility: COLOR_ATTACHMENT_OPTIMAL ->
  SHADER_READ_ONLY_OPTIMAL, the colour writes of COLOR_ATTACHMENT_OUTPUT made visible to the
  FRAGMENT_SHADER's sampled reads), then a render pass whose subpass 0 draws the effect, sampling
  the handoff image through a COMBINED_IMAGE_SAMPLER (linear, clamp to edge: FXAA samples between
  pixels), with its parameters as push constants; and, when per-pixel effects follow (the
  segment's *tail*), a subpass 1 that runs them reading subpass 0's result as an input attachment,
  exactly as the scene's pass does (post.PostSubpass; dependency 0 -> 1 BY_REGION).
- the segment's result is the output (last segment) or the next handoff image.

Where the wgpu path stores an rgba16float (or 8-bit sRGB) intermediate between two of its effect
passes, this path stores the same format at the same points of the chain (the handoff images and
subpass 0's attachment), so the only difference left between the paths is the one the per-pixel
subpasses already have: several per-pixel effects in one subpass keep float32 between them.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from contextlib import ExitStack
from dataclasses import dataclass

import vulkan as vk

from wgpurender.core.course.effects import EffectStep
from wgpurender.core.plan import RenderPlan
from wgpurender.raw_path.device import descriptors
from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.images import Image, create_image, transition, vk_format
from wgpurender.raw_path.device.pipeline import (
    PipelineDesc,
    create_pipeline,
    create_pipeline_layout,
    set_viewport_and_scissor,
)
from wgpurender.raw_path.device.renderpass import (
    COLOR_OPTIMAL,
    COLOR_STAGE,
    COLOR_WRITE,
    attachment,
    begin,
    clear_color,
    create_framebuffer,
    create_render_pass,
    dependency,
    into_pass,
    out_to_transfer,
    ref,
)
from wgpurender.raw_path.post.chain import PostSubpass

FRAGMENT = vk.VK_SHADER_STAGE_FRAGMENT_BIT
GRAPHICS = vk.VK_PIPELINE_BIND_POINT_GRAPHICS
READ_ONLY = vk.VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL
TRANSFER_SRC = vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL
DONT_LOAD, STORE = vk.VK_ATTACHMENT_LOAD_OP_DONT_CARE, vk.VK_ATTACHMENT_STORE_OP_STORE
# effect -> (fragment shader in shaders_glsl/, its push constants in declaration order)
NEIGHBOUR_SHADERS = {
    "fxaa": ("post_fxaa.frag", ("subpix", "edge_threshold", "edge_threshold_min")),
    "sharpen": ("post_sharpen.frag", ("strength",)),
}
HANDOFF_USAGE = vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | vk.VK_IMAGE_USAGE_SAMPLED_BIT
TAIL_INPUT_USAGE = (vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | vk.VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT
                    | vk.VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT)


@dataclass(frozen=True)
class Segment:
    """A neighbourhood effect and the per-pixel effects after it, up to the next neighbourhood effect."""

    effect: EffectStep
    tail: tuple[EffectStep, ...]


def scene_image_format(plan: RenderPlan) -> str:
    return plan.attachment("scene_color").format


def is_neighbourhood(p: EffectStep) -> bool:
    return p.effect in NEIGHBOUR_SHADERS


def split_chain(passes: Sequence[EffectStep]) -> tuple[tuple[EffectStep, ...], tuple[Segment, ...]]:
    """(head, segments): the per-pixel effects before the first neighbourhood effect, then one segment each."""
    cuts = [i for i, p in enumerate(passes) if is_neighbourhood(p)] + [len(passes)]
    head = tuple(passes[:cuts[0]])
    segments = tuple(Segment(passes[a], tuple(passes[a + 1:b])) for a, b in zip(cuts, cuts[1:], strict=False))
    return head, segments


def push_constants(p: EffectStep) -> bytes:
    params = dict(p.params)
    return struct.pack(f"<{len(NEIGHBOUR_SHADERS[p.effect][1])}f",
                       *(float(params[name]) for name in NEIGHBOUR_SHADERS[p.effect][1]))


def create_linear_clamp_sampler(ctx: VulkanContext, owned: ExitStack):
    """Bilinear, clamp to edge, one mip level: the wgpu path's post sampler (post/passes.py)."""
    edge = vk.VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE
    info = vk.VkSamplerCreateInfo(magFilter=vk.VK_FILTER_LINEAR, minFilter=vk.VK_FILTER_LINEAR,
                                  mipmapMode=vk.VK_SAMPLER_MIPMAP_MODE_NEAREST, addressModeU=edge,
                                  addressModeV=edge, addressModeW=edge, minLod=0.0, maxLod=32.0)
    sampler = vk.vkCreateSampler(ctx.device, info, None)
    owned.callback(vk.vkDestroySampler, ctx.device, sampler, None)
    return sampler


class NeighbourhoodPass:
    """One segment: barrier, then a render pass (effect subpass, optional per-pixel tail subpass)."""

    def __init__(self, ctx: VulkanContext, owned: ExitStack, plan: RenderPlan, segment: Segment, source: Image,
                 out_format: str, final: bool, wgpu_intermediates: bool = False) -> None:
        self.ctx, self.owned, self.segment, self.source, self.final = ctx, owned, segment, source, final
        self.size = plan.size
        # subpass 0's result, read by the tail: the scene image's format (the wgpu path's fused pass keeps float32
        # there; an 8-bit knob post_intermediate would add a rounding the wgpu path does not have)
        mid_format = scene_image_format(plan)
        effect_format = mid_format if segment.tail else out_format
        self.render_pass = self._create_render_pass(vk_format(effect_format), vk_format(out_format))
        self.mid = None
        if segment.tail:
            self.mid = create_image(ctx, owned, self.size, mid_format, TAIL_INPUT_USAGE, lazy=True)
        self._setup_effect(source)
        self.tail = None
        if segment.tail:
            self.tail = PostSubpass(ctx, owned, plan, self.render_pass, self.mid, wgpu_intermediates,
                                    passes=segment.tail, subpass=1)

    def _create_render_pass(self, effect_vkf: int, out_vkf: int):
        """Attachment 0: the effect's result; with a tail, attachment 1: the tail's, and 0 is its input."""
        last_layout = TRANSFER_SRC if self.final else COLOR_OPTIMAL
        no_clear = clear_color((0.0, 0.0, 0.0, 0.0))  # every attachment is fully overwritten: nothing cleared
        effect_ref = ref(0)
        draw = vk.VkSubpassDescription(pipelineBindPoint=GRAPHICS, pColorAttachments=[effect_ref])
        if not self.segment.tail:
            attachments = [attachment(effect_vkf, 1, DONT_LOAD, STORE, last_layout)]
            subpasses, deps = [draw], [into_pass()]
        else:
            attachments = [attachment(effect_vkf, 1, DONT_LOAD, vk.VK_ATTACHMENT_STORE_OP_DONT_CARE, READ_ONLY),
                           attachment(out_vkf, 1, DONT_LOAD, STORE, last_layout)]
            input_ref, out_ref = ref(0, READ_ONLY), ref(1)
            tail = vk.VkSubpassDescription(pipelineBindPoint=GRAPHICS, pInputAttachments=[input_ref],
                                           pColorAttachments=[out_ref])
            subpasses = [draw, tail]
            deps = [into_pass(),
                    dependency(0, 1, COLOR_STAGE, COLOR_WRITE, vk.VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                               vk.VK_ACCESS_INPUT_ATTACHMENT_READ_BIT, by_region=True),
                    dependency(vk.VK_SUBPASS_EXTERNAL, 1, COLOR_STAGE, 0, COLOR_STAGE, COLOR_WRITE)]
        if self.final:
            deps.append(out_to_transfer(len(subpasses) - 1))
        return create_render_pass(self.ctx, self.owned, attachments, subpasses, deps, [no_clear] * len(attachments))

    def _setup_effect(self, source: Image) -> None:
        ctx, owned = self.ctx, self.owned
        shader, names = NEIGHBOUR_SHADERS[self.segment.effect.effect]
        bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, FRAGMENT)]
        set_layout = descriptors.create_set_layout(ctx, owned, bindings)
        pool = descriptors.create_pool(ctx, owned, [bindings])
        (self.set,) = descriptors.allocate_sets(ctx, pool, [set_layout])
        sampler = create_linear_clamp_sampler(ctx, owned)
        descriptors.update(ctx, [descriptors.write_image(
            self.set, 0, source.view, READ_ONLY, vk.VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, sampler)])
        self.push = push_constants(self.segment.effect)
        push_range = vk.VkPushConstantRange(stageFlags=FRAGMENT, offset=0, size=len(self.push))
        self.layout = create_pipeline_layout(ctx, owned, [set_layout], [push_range])
        self.pipeline = create_pipeline(ctx, owned, PipelineDesc("fullscreen.vert", shader), self.layout,
                                        self.render_pass)

    def record(self, cmd, target: Image) -> None:
        """The barrier on the source, then the pass into ``target`` (the output or the next handoff image)."""
        transition(cmd, self.source, COLOR_OPTIMAL, READ_ONLY)
        views = [self.mid, target] if self.mid is not None else [target]
        framebuffer = create_framebuffer(self.ctx, self.owned, self.render_pass, views)
        begin(cmd, self.render_pass, framebuffer, self.size)
        set_viewport_and_scissor(cmd, self.size)  # flipped, as the scene's post subpass
        vk.vkCmdBindPipeline(cmd, GRAPHICS, self.pipeline)
        vk.vkCmdBindDescriptorSets(cmd, GRAPHICS, self.layout, 0, 1, [self.set], 0, None)
        vk.vkCmdPushConstants(cmd, self.layout, FRAGMENT, 0, len(self.push), vk.ffi.from_buffer(self.push))
        vk.vkCmdDraw(cmd, 3, 1, 0, 0)
        if self.tail is not None:
            vk.vkCmdNextSubpass(cmd, vk.VK_SUBPASS_CONTENTS_INLINE)
            self.tail.record(cmd, self.size)
        vk.vkCmdEndRenderPass(cmd)
