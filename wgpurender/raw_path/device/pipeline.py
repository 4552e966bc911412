"""Course concepts: pipeline layout (set layouts + push constant ranges), pipeline cache, graphics pipeline.

A graphics pipeline bakes in everything fixed: shader stages (SPIR-V modules),
vertex input (bindings and attributes), input assembly, viewport state,
rasterizer, multisample, depth/stencil and colour blending, for one subpass of
one render pass. Viewport and scissor are left *dynamic* (set per command buffer)
so a pipeline does not depend on the image size.

The VkPipelineCache is loaded from ~/.cache/wgpurender/ at start-up and written
back at exit: the driver reuses compiled pipelines across runs. Its header names
the vendor, device and driver UUID; a driver that sees another device's cache
ignores it, so a stale file is harmless.
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass, field

import vulkan as vk

from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.shaders import create_shader_module

ALL_COLOR = (
    vk.VK_COLOR_COMPONENT_R_BIT | vk.VK_COLOR_COMPONENT_G_BIT
    | vk.VK_COLOR_COMPONENT_B_BIT | vk.VK_COLOR_COMPONENT_A_BIT
)


@dataclass
class PipelineDesc:
    """What differs between our pipelines; everything else is the course's defaults."""

    vert: str
    frag: str
    vertex_bindings: list = field(default_factory=list)  # VkVertexInputBindingDescription
    vertex_attributes: list = field(default_factory=list)  # VkVertexInputAttributeDescription
    samples: int = 1
    cull_mode: int = vk.VK_CULL_MODE_NONE
    front_face: int = vk.VK_FRONT_FACE_COUNTER_CLOCKWISE
    depth_test: bool = False
    subpass: int = 0
    defines: tuple[str, ...] = ()  # glslc -D definitions for both shaders (shader variants)
    blend: bool = False  # source-over alpha blending, no depth writes (glTF alphaMode BLEND)
    topology: int = vk.VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST  # POINT_LIST / LINE_LIST: glTF points and lines


# -- layout and pipeline --------------------------------------------------------------

def create_pipeline_layout(ctx: VulkanContext, owned: ExitStack, set_layouts: list = (), push_ranges: list = ()):
    """vkCreatePipelineLayout: the descriptor set layouts (set 0, 1, ...) and push constant ranges."""
    info = vk.VkPipelineLayoutCreateInfo(pSetLayouts=list(set_layouts), pPushConstantRanges=list(push_ranges))
    layout = vk.vkCreatePipelineLayout(ctx.device, info, None)
    owned.callback(vk.vkDestroyPipelineLayout, ctx.device, layout, None)
    return layout


def _blend_attachment(blend: bool):
    """No blending, or source-over: rgb = src * a + dst * (1 - a), alpha = a + dst_a * (1 - a)."""
    if not blend:
        return vk.VkPipelineColorBlendAttachmentState(blendEnable=vk.VK_FALSE, colorWriteMask=ALL_COLOR)
    return vk.VkPipelineColorBlendAttachmentState(
        blendEnable=vk.VK_TRUE, colorWriteMask=ALL_COLOR,
        srcColorBlendFactor=vk.VK_BLEND_FACTOR_SRC_ALPHA, dstColorBlendFactor=vk.VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA,
        colorBlendOp=vk.VK_BLEND_OP_ADD, srcAlphaBlendFactor=vk.VK_BLEND_FACTOR_ONE,
        dstAlphaBlendFactor=vk.VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA, alphaBlendOp=vk.VK_BLEND_OP_ADD)


def create_pipeline(ctx: VulkanContext, owned: ExitStack, desc: PipelineDesc, layout, render_pass):
    """vkCreateGraphicsPipelines with the state structures of the course, one per fixed-function stage."""
    vert = create_shader_module(ctx.device, desc.vert, desc.defines)
    frag = create_shader_module(ctx.device, desc.frag, desc.defines)
    try:
        stages = [
            vk.VkPipelineShaderStageCreateInfo(stage=vk.VK_SHADER_STAGE_VERTEX_BIT, module=vert, pName="main"),
            vk.VkPipelineShaderStageCreateInfo(stage=vk.VK_SHADER_STAGE_FRAGMENT_BIT, module=frag, pName="main"),
        ]
        vertex_input = vk.VkPipelineVertexInputStateCreateInfo(
            pVertexBindingDescriptions=desc.vertex_bindings, pVertexAttributeDescriptions=desc.vertex_attributes
        )
        assembly = vk.VkPipelineInputAssemblyStateCreateInfo(
            topology=desc.topology, primitiveRestartEnable=vk.VK_FALSE
        )
        viewport = vk.VkPipelineViewportStateCreateInfo(viewportCount=1, scissorCount=1)  # both dynamic
        raster = vk.VkPipelineRasterizationStateCreateInfo(
            polygonMode=vk.VK_POLYGON_MODE_FILL, cullMode=desc.cull_mode, frontFace=desc.front_face, lineWidth=1.0
        )
        multisample = vk.VkPipelineMultisampleStateCreateInfo(rasterizationSamples=desc.samples)
        depth = vk.VkPipelineDepthStencilStateCreateInfo(
            depthTestEnable=desc.depth_test, depthWriteEnable=desc.depth_test and not desc.blend,
            depthCompareOp=vk.VK_COMPARE_OP_LESS, maxDepthBounds=1.0,
        )
        blend_attachment = _blend_attachment(desc.blend)
        blend = vk.VkPipelineColorBlendStateCreateInfo(pAttachments=[blend_attachment])
        dynamic = vk.VkPipelineDynamicStateCreateInfo(
            pDynamicStates=[vk.VK_DYNAMIC_STATE_VIEWPORT, vk.VK_DYNAMIC_STATE_SCISSOR]
        )
        info = vk.VkGraphicsPipelineCreateInfo(
            pStages=stages, pVertexInputState=vertex_input, pInputAssemblyState=assembly, pViewportState=viewport,
            pRasterizationState=raster, pMultisampleState=multisample,
            pDepthStencilState=depth if desc.depth_test else None, pColorBlendState=blend,
            pDynamicState=dynamic, layout=layout, renderPass=render_pass.handle, subpass=desc.subpass,
        )
        pipeline = vk.vkCreateGraphicsPipelines(ctx.device, ctx.pipeline_cache, 1, [info], None)[0]
    finally:
        # a shader module is only needed while pipelines are created from it
        vk.vkDestroyShaderModule(ctx.device, vert, None)
        vk.vkDestroyShaderModule(ctx.device, frag, None)
    owned.callback(vk.vkDestroyPipeline, ctx.device, pipeline, None)
    return pipeline


def set_viewport_and_scissor(cmd, size: tuple[int, int]) -> None:
    """The dynamic viewport, flipped: y = height, height = -height.

    Vulkan's NDC y points down (y = -1 is the top row), wgpu's (like OpenGL's and
    D3D's) points up. Our shaders use wgpu's y-up positions unchanged, so to get
    the same image the viewport maps NDC y = +1 to the top row instead: a
    negative height (allowed since VK_KHR_maintenance1, core in Vulkan 1.1)
    with its origin on the bottom edge. Culling needs no change either:
    front_face is decided in framebuffer space, after the flip, so a triangle
    that is counter-clockwise as seen in the image is counter-clockwise in both
    APIs. (wgpu's own Vulkan backend flips its viewport the same way.)
    """
    width, height = size
    viewport = vk.VkViewport(x=0.0, y=float(height), width=float(width), height=-float(height),
                             minDepth=0.0, maxDepth=1.0)
    vk.vkCmdSetViewport(cmd, 0, 1, [viewport])
    scissor = vk.VkRect2D(offset=vk.VkOffset2D(x=0, y=0), extent=vk.VkExtent2D(width=width, height=height))
    vk.vkCmdSetScissor(cmd, 0, 1, [scissor])
