"""Course concepts: attachment descriptions and references, subpasses and dependencies, render pass, framebuffer.

A VkRenderPass describes the attachments (format, samples, load/store ops, the
layout on entry and on exit), the subpasses (which attachment each uses as
colour, resolve or input, and in which layout: VkAttachmentReference), and the
dependencies between subpasses and with the commands outside the pass. A
VkFramebuffer binds concrete image views to those attachment slots.

Three shapes are used by the stages:
- :func:`single_pass`: one subpass, one colour attachment (plus a resolve
  attachment with MSAA), ending in TRANSFER_SRC_OPTIMAL for the readback copy.
- :func:`msaa_post_pass`: two subpasses. Subpass 0 draws into a multisampled
  attachment resolved into a single-sample one; subpass 1 reads the resolved
  image as an input attachment (subpassLoad) and writes the post-processed
  output. The dependency 0 -> 1 orders the resolve writes before the input
  attachment reads, per region (pixel-local: no pixel reads another's).
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass

import vulkan as vk

from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.images import DEPTH_FORMAT, Image, vk_format

COLOR_OPTIMAL = vk.VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL
COLOR_STAGE = vk.VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT
COLOR_WRITE = vk.VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT
DEPTH_OPTIMAL = vk.VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL
DEPTH_STAGES = vk.VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | vk.VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT
DEPTH_WRITE = vk.VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT


@dataclass
class RenderPass:
    handle: object
    subpass_count: int
    clears: list  # one VkClearValue slot per attachment (ignored for attachments that do not clear)


def attachment(fmt: int, samples: int, load: int, store: int, final_layout: int):
    """VkAttachmentDescription. Every pass here starts from UNDEFINED: old contents are never kept."""
    return vk.VkAttachmentDescription(
        format=fmt, samples=samples, loadOp=load, storeOp=store,
        stencilLoadOp=vk.VK_ATTACHMENT_LOAD_OP_DONT_CARE, stencilStoreOp=vk.VK_ATTACHMENT_STORE_OP_DONT_CARE,
        initialLayout=vk.VK_IMAGE_LAYOUT_UNDEFINED, finalLayout=final_layout,
    )


def ref(index: int, layout: int = COLOR_OPTIMAL):
    """VkAttachmentReference: attachment ``index`` of the pass, in ``layout`` during the subpass."""
    return vk.VkAttachmentReference(attachment=index, layout=layout)


def dependency(src: int, dst: int, src_stage: int, src_access: int, dst_stage: int, dst_access: int,
               by_region: bool = False):
    return vk.VkSubpassDependency(
        srcSubpass=src, dstSubpass=dst, srcStageMask=src_stage, srcAccessMask=src_access,
        dstStageMask=dst_stage, dstAccessMask=dst_access,
        dependencyFlags=vk.VK_DEPENDENCY_BY_REGION_BIT if by_region else 0,
    )


def into_pass(depth: bool = False) -> object:
    """EXTERNAL -> 0: the layout transition from UNDEFINED and the first colour (and depth) writes wait
    for earlier output (none in a fresh image, but this is the dependency a reused image needs)."""
    stages = COLOR_STAGE | (DEPTH_STAGES if depth else 0)
    return dependency(vk.VK_SUBPASS_EXTERNAL, 0, stages, 0, stages, COLOR_WRITE | (DEPTH_WRITE if depth else 0))


def out_to_transfer(last: int) -> object:
    """last -> EXTERNAL: colour writes (and resolves) finish before the readback copy reads the image."""
    return dependency(last, vk.VK_SUBPASS_EXTERNAL, COLOR_STAGE, COLOR_WRITE, vk.VK_PIPELINE_STAGE_TRANSFER_BIT,
                      vk.VK_ACCESS_TRANSFER_READ_BIT)


def create_render_pass(ctx: VulkanContext, owned: ExitStack, attachments: list, subpasses: list,
                       dependencies: list, clears: list) -> RenderPass:
    info = vk.VkRenderPassCreateInfo(pAttachments=attachments, pSubpasses=subpasses, pDependencies=dependencies)
    handle = vk.vkCreateRenderPass(ctx.device, info, None)
    owned.callback(vk.vkDestroyRenderPass, ctx.device, handle, None)
    return RenderPass(handle, len(subpasses), clears)


def clear_color(rgba) -> object:
    return vk.VkClearValue(color=vk.VkClearColorValue(float32=list(rgba)))


def single_pass(ctx: VulkanContext, owned: ExitStack, fmt: str, samples: int, clear_rgba,
                final_layout: int = vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, depth: bool = False) -> RenderPass:
    """One subpass drawing into attachment 0; with MSAA, attachment 0 is the multisampled image and
    attachment 1 the single-sample image it is resolved into (pResolveAttachments) at the end.
    With ``depth``, a D32 depth attachment (same sample count) comes last, cleared to 1.0.

    The multisampled attachment's storeOp is DONT_CARE: only its resolve is kept; so is depth's.
    """
    vkf = vk_format(fmt)
    load, store = vk.VK_ATTACHMENT_LOAD_OP_CLEAR, vk.VK_ATTACHMENT_STORE_OP_STORE
    dont = vk.VK_ATTACHMENT_STORE_OP_DONT_CARE
    color_ref = ref(0)
    if samples == 1:
        attachments = [attachment(vkf, 1, load, store, final_layout)]
        subpass = vk.VkSubpassDescription(pipelineBindPoint=vk.VK_PIPELINE_BIND_POINT_GRAPHICS,
                                          pColorAttachments=[color_ref])
    else:
        resolve_ref = ref(1)
        attachments = [
            attachment(vkf, samples, load, dont, COLOR_OPTIMAL),
            attachment(vkf, 1, vk.VK_ATTACHMENT_LOAD_OP_DONT_CARE, store, final_layout),
        ]
        subpass = vk.VkSubpassDescription(pipelineBindPoint=vk.VK_PIPELINE_BIND_POINT_GRAPHICS,
                                          pColorAttachments=[color_ref], pResolveAttachments=[resolve_ref])
    clears = [clear_color(clear_rgba)] * len(attachments)
    if depth:
        depth_ref = ref(len(attachments), DEPTH_OPTIMAL)
        attachments.append(attachment(DEPTH_FORMAT, samples, load, dont, DEPTH_OPTIMAL))
        subpass.pDepthStencilAttachment = vk.ffi.addressof(depth_ref)
        clears.append(vk.VkClearValue(depthStencil=vk.VkClearDepthStencilValue(depth=1.0, stencil=0)))
    deps = [into_pass(depth), out_to_transfer(0)]
    return create_render_pass(ctx, owned, attachments, [subpass], deps, clears)


def msaa_post_pass(ctx: VulkanContext, owned: ExitStack, scene_fmt: str, out_fmt: str, samples: int,
                   clear_rgba) -> RenderPass:
    """Attachments: 0 multisampled scene colour, 1 its resolve (then an input attachment), 2 the output.

    Subpass 0: colour 0, resolve into 1. Subpass 1: input 1 (SHADER_READ_ONLY_OPTIMAL, the render
    pass transitions it between the subpasses), colour 2. Neither 0 nor 1 is stored: they live only
    inside the pass (on a tiler they could stay in tile memory).
    """
    scene, out = vk_format(scene_fmt), vk_format(out_fmt)
    dont_load, dont_store = vk.VK_ATTACHMENT_LOAD_OP_DONT_CARE, vk.VK_ATTACHMENT_STORE_OP_DONT_CARE
    read_only = vk.VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL
    attachments = [
        attachment(scene, samples, vk.VK_ATTACHMENT_LOAD_OP_CLEAR, dont_store, COLOR_OPTIMAL),
        attachment(scene, 1, dont_load, dont_store, read_only),
        # fully overwritten by the post pass's full-screen triangle, so nothing to load or clear
        attachment(out, 1, dont_load, vk.VK_ATTACHMENT_STORE_OP_STORE, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL),
    ]
    scene_ref, resolve_ref, input_ref, out_ref = ref(0), ref(1), ref(1, read_only), ref(2)
    draw = vk.VkSubpassDescription(pipelineBindPoint=vk.VK_PIPELINE_BIND_POINT_GRAPHICS,
                                   pColorAttachments=[scene_ref], pResolveAttachments=[resolve_ref])
    post = vk.VkSubpassDescription(pipelineBindPoint=vk.VK_PIPELINE_BIND_POINT_GRAPHICS,
                                   pInputAttachments=[input_ref], pColorAttachments=[out_ref])
    deps = [
        into_pass(),
        dependency(0, 1, COLOR_STAGE, COLOR_WRITE, vk.VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                   vk.VK_ACCESS_INPUT_ATTACHMENT_READ_BIT, by_region=True),
        dependency(vk.VK_SUBPASS_EXTERNAL, 1, COLOR_STAGE, 0, COLOR_STAGE, COLOR_WRITE),  # output's first write
        out_to_transfer(1),
    ]
    return create_render_pass(ctx, owned, attachments, [draw, post], deps, [clear_color(clear_rgba)] * 3)


def create_framebuffer(ctx: VulkanContext, owned: ExitStack, render_pass: RenderPass, images: list[Image]):
    """Views in attachment order; all attachments share the framebuffer's size."""
    width, height = images[0].size
    info = vk.VkFramebufferCreateInfo(
        renderPass=render_pass.handle, pAttachments=[im.view for im in images], width=width, height=height, layers=1
    )
    handle = vk.vkCreateFramebuffer(ctx.device, info, None)
    owned.callback(vk.vkDestroyFramebuffer, ctx.device, handle, None)
    return handle


def begin(cmd, render_pass: RenderPass, framebuffer, size: tuple[int, int]) -> None:
    """vkCmdBeginRenderPass over the whole framebuffer; clear values indexed like the attachments."""
    area = vk.VkRect2D(offset=vk.VkOffset2D(x=0, y=0), extent=vk.VkExtent2D(width=size[0], height=size[1]))
    info = vk.VkRenderPassBeginInfo(renderPass=render_pass.handle, framebuffer=framebuffer, renderArea=area,
                                    pClearValues=render_pass.clears)
    vk.vkCmdBeginRenderPass(cmd, info, vk.VK_SUBPASS_CONTENTS_INLINE)
