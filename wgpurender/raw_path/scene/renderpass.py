"""The scene's render pass: subpass 0 draws the models, subpass 1 runs the post chain on the result.

Attachments, in this order (each only when the plan needs it):

- ``msaa_color`` (msaa 4): the multisampled colour subpass 0 draws into; resolved at the end of
  subpass 0, its samples discarded (storeOp DONT_CARE, TRANSIENT + lazily allocated memory);
- ``scene_color`` (with a post chain): the single-sample scene image: resolve target of subpass 0
  (or its colour attachment at msaa 1), then subpass 1's *input attachment*. Never stored: it
  lives only inside the pass, which on a tiling GPU lets it stay in tile memory;
- ``depth``: D32, as many samples as the colour, cleared to 1.0, not stored;
- ``output``: what the readback copies, written by subpass 1 (or by subpass 0 without a chain).

Dependencies: EXTERNAL -> 0 (first colour and depth writes), 0 -> 1 BY_REGION (the resolve's
colour writes before subpass 1's fragment shader reads the input attachment, pixel by pixel:
no fragment reads another pixel, so a tiler may run subpass 1 tile by tile right after subpass 0),
EXTERNAL -> 1 (the output's first write), last -> EXTERNAL (writes before the readback copy).

With a neighbourhood effect (fxaa, sharpen) in the chain, subpass 1 runs only the per-pixel effects
before it (the chain's *head*) and the pass ends in a stored ``handoff`` image instead of the
output; an explicit image barrier then makes it readable by the neighbourhood pass's sampler
(neighbourhood.py). A chain that starts with a neighbourhood effect has no subpass 1: subpass 0
resolves straight into ``handoff``.

wgpu cannot express any of this: its scene pass resolves into a texture that the first post
pass samples in a render pass of its own (wgpurender/wgpu_path/scene/frame.py).
"""

from __future__ import annotations

from collections.abc import Sequence
from contextlib import ExitStack
from dataclasses import dataclass

import vulkan as vk

from wgpurender.core.course.effects import EffectStep
from wgpurender.core.plan import RenderPlan
from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.images import DEPTH_FORMAT, vk_format
from wgpurender.raw_path.device.renderpass import (
    COLOR_STAGE,
    COLOR_WRITE,
    DEPTH_OPTIMAL,
    RenderPass,
    attachment,
    clear_color,
    create_render_pass,
    dependency,
    into_pass,
    out_to_transfer,
    ref,
)

CLEAR, LOAD_DONT_CARE = vk.VK_ATTACHMENT_LOAD_OP_CLEAR, vk.VK_ATTACHMENT_LOAD_OP_DONT_CARE
STORE, STORE_DONT_CARE = vk.VK_ATTACHMENT_STORE_OP_STORE, vk.VK_ATTACHMENT_STORE_OP_DONT_CARE
COLOR_OPTIMAL = vk.VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL
READ_ONLY = vk.VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL
TRANSFER_SRC = vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL


@dataclass(frozen=True)
class AttachmentSpec:
    """One attachment slot of the pass: its role name, wgpu-style format name and sample count."""

    name: str
    format: str
    samples: int


@dataclass
class SceneRenderPass:
    render_pass: RenderPass
    attachments: list[AttachmentSpec]  # in attachment order: the framebuffer's views follow it

    @property
    def has_post(self) -> bool:
        return self.render_pass.subpass_count == 2


def scene_format(plan: RenderPlan) -> str:
    """The format subpass 0 draws in: the plan's scene image, or the output without a chain."""
    return plan.attachment("scene_color").format if plan.has_attachment("scene_color") else plan.output_format


def handoff_format(plan: RenderPlan) -> str:
    """The format of the images a neighbourhood pass samples after per-pixel effects (the wgpu path's post
    intermediates): the knob post_intermediate, or the scene image's format ("auto": today's image; "none" is
    refused by support.py before a frame is built)."""
    knob = plan.knobs.post_intermediate
    return scene_format(plan) if knob in ("auto", "none") else knob


def create_scene_render_pass(ctx: VulkanContext, owned: ExitStack, plan: RenderPlan,
                             head: Sequence[EffectStep] | None = None, handoff: bool = False) -> SceneRenderPass:
    """The scene's pass. ``head``: the per-pixel effects of subpass 1 (default: the whole chain; empty: no
    subpass 1). ``handoff``: the pass ends in the ``handoff`` image, which a neighbourhood pass samples next
    (neighbourhood.py), instead of the output: stored, left in COLOR_ATTACHMENT_OPTIMAL for the explicit
    barrier that follows the pass, and no dependency to the readback copy."""
    head = plan.post_steps if head is None else tuple(head)
    has_post = bool(head)
    samples, depth = plan.msaa, plan.has_attachment("depth")
    drawn_fmt = scene_format(plan)
    last_name = "handoff" if handoff else "output"
    last_layout = COLOR_OPTIMAL if handoff else TRANSFER_SRC
    target = "scene_color" if has_post else last_name  # what subpass 0's image ends up in (single-sample)
    store = STORE_DONT_CARE if has_post else STORE
    final = READ_ONLY if has_post else last_layout
    specs, descriptions, clears = [], [], []

    def add(spec: AttachmentSpec, description, clear) -> int:
        specs.append(spec)
        descriptions.append(description)
        clears.append(clear)
        return len(specs) - 1

    clear = clear_color(plan.scene_pass.clear_color)
    vkf = vk_format(drawn_fmt)
    if samples > 1:
        color = add(AttachmentSpec("msaa_color", drawn_fmt, samples),
                    attachment(vkf, samples, CLEAR, STORE_DONT_CARE, COLOR_OPTIMAL), clear)
        # the resolve overwrites every pixel: nothing to load
        resolved = add(AttachmentSpec(target, drawn_fmt, 1), attachment(vkf, 1, LOAD_DONT_CARE, store, final), clear)
    else:
        color = add(AttachmentSpec(target, drawn_fmt, 1), attachment(vkf, 1, CLEAR, store, final), clear)
        resolved = None
    depth_index = None
    if depth:
        depth_index = add(AttachmentSpec("depth", "depth32float", samples),
                          attachment(DEPTH_FORMAT, samples, CLEAR, STORE_DONT_CARE, DEPTH_OPTIMAL),
                          vk.VkClearValue(depthStencil=vk.VkClearDepthStencilValue(depth=1.0, stencil=0)))
    output = None
    if has_post:
        # fully overwritten by the post chain's full-screen triangle: nothing to load or clear
        out_fmt = handoff_format(plan) if handoff else plan.output_format
        output = add(AttachmentSpec(last_name, out_fmt, 1),
                     attachment(vk_format(out_fmt), 1, LOAD_DONT_CARE, STORE, last_layout), clear)

    # The references must outlive vkCreateRenderPass: keep every one in a local.
    color_ref = ref(color)
    resolve_refs = [ref(resolved)] if resolved is not None else None
    draw = vk.VkSubpassDescription(pipelineBindPoint=vk.VK_PIPELINE_BIND_POINT_GRAPHICS,
                                   pColorAttachments=[color_ref], pResolveAttachments=resolve_refs)
    if depth_index is not None:
        depth_ref = ref(depth_index, DEPTH_OPTIMAL)
        draw.pDepthStencilAttachment = vk.ffi.addressof(depth_ref)
    subpasses = [draw]
    deps = [into_pass(depth)]
    if has_post:
        scene_index = resolved if resolved is not None else color
        input_ref, out_ref = ref(scene_index, READ_ONLY), ref(output)
        post = vk.VkSubpassDescription(pipelineBindPoint=vk.VK_PIPELINE_BIND_POINT_GRAPHICS,
                                       pInputAttachments=[input_ref], pColorAttachments=[out_ref])
        subpasses.append(post)
        deps += [
            dependency(0, 1, COLOR_STAGE, COLOR_WRITE, vk.VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                       vk.VK_ACCESS_INPUT_ATTACHMENT_READ_BIT, by_region=True),
            dependency(vk.VK_SUBPASS_EXTERNAL, 1, COLOR_STAGE, 0, COLOR_STAGE, COLOR_WRITE),
        ]
    if not handoff:
        deps.append(out_to_transfer(len(subpasses) - 1))
    handle = create_render_pass(ctx, owned, descriptions, subpasses, deps, clears)
    return SceneRenderPass(handle, specs)
