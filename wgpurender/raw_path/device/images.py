"""Course concepts: images, image views, subresources, layouts and layout transitions.

A VkImage is memory plus a description (format, extent, samples, usage); a
VkImageView says which part of it (its subresource range: aspect, mip levels,
array layers) a framebuffer or a descriptor sees, and how. An image's texels are
in one *layout* at a time (UNDEFINED, COLOR_ATTACHMENT_OPTIMAL,
TRANSFER_SRC/DST_OPTIMAL, SHADER_READ_ONLY_OPTIMAL...); moving between layouts is
an image memory barrier recorded with vkCmdPipelineBarrier, whose stage and
access masks say which earlier writes must finish and become visible before
which later accesses may start.
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass

import numpy as np
import vulkan as vk

from wgpurender.core.errors import UserError
from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.memory import allocate

# wgpu format name -> (VkFormat, bytes per texel, numpy dtype of a channel): the same names as targets.COLOR_FORMATS
FORMATS: dict[str, tuple[int, int, type]] = {
    "rgba8unorm": (vk.VK_FORMAT_R8G8B8A8_UNORM, 4, np.uint8),
    "rgba8unorm-srgb": (vk.VK_FORMAT_R8G8B8A8_SRGB, 4, np.uint8),
    "rgba16float": (vk.VK_FORMAT_R16G16B16A16_SFLOAT, 8, np.float16),
}
DEPTH_FORMAT = vk.VK_FORMAT_D32_SFLOAT

# What touches an image in each layout: (pipeline stage, access mask). A barrier out of a
# layout waits for that stage's writes; a barrier into a layout makes them visible to it.
LAYOUT_ACCESS: dict[int, tuple[int, int]] = {
    vk.VK_IMAGE_LAYOUT_UNDEFINED: (vk.VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0),
    vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL: (vk.VK_PIPELINE_STAGE_TRANSFER_BIT, vk.VK_ACCESS_TRANSFER_WRITE_BIT),
    vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL: (vk.VK_PIPELINE_STAGE_TRANSFER_BIT, vk.VK_ACCESS_TRANSFER_READ_BIT),
    vk.VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL: (
        vk.VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
        vk.VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | vk.VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
    ),
    vk.VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL: (
        vk.VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, vk.VK_ACCESS_SHADER_READ_BIT
    ),
}


@dataclass
class Image:
    handle: object
    view: object
    format: str
    vk_format: int
    size: tuple[int, int]
    samples: int
    aspect: int


def vk_format(fmt: str) -> int:
    if fmt not in FORMATS:
        raise UserError(f"unsupported colour format {fmt!r}: choose one of {', '.join(FORMATS)}")
    return FORMATS[fmt][0]


def subresource_range(aspect: int = vk.VK_IMAGE_ASPECT_COLOR_BIT):
    """Mip 0, layer 0: all our images have one of each."""
    return vk.VkImageSubresourceRange(aspectMask=aspect, baseMipLevel=0, levelCount=1, baseArrayLayer=0, layerCount=1)


def subresource_layers(aspect: int = vk.VK_IMAGE_ASPECT_COLOR_BIT):
    """The copy commands' way of naming a subresource: one mip level, a range of layers."""
    return vk.VkImageSubresourceLayers(aspectMask=aspect, mipLevel=0, baseArrayLayer=0, layerCount=1)


def create_image(
    ctx: VulkanContext, owned: ExitStack, size: tuple[int, int], fmt: str, usage: int, samples: int = 1,
    lazy: bool = False,
) -> Image:
    """A 2D image, its memory and a view of all of it, destroyed when ``owned`` closes.

    ``lazy``: a transient attachment (multisampled colour that is resolved and
    discarded): LAZILY_ALLOCATED memory is preferred, where the GPU offers it,
    so the samples may never need real memory.
    """
    vkf = DEPTH_FORMAT if fmt == "depth32float" else vk_format(fmt)
    aspect = vk.VK_IMAGE_ASPECT_DEPTH_BIT if fmt == "depth32float" else vk.VK_IMAGE_ASPECT_COLOR_BIT
    info = vk.VkImageCreateInfo(
        imageType=vk.VK_IMAGE_TYPE_2D, format=vkf, extent=vk.VkExtent3D(width=size[0], height=size[1], depth=1),
        mipLevels=1, arrayLayers=1, samples=samples, tiling=vk.VK_IMAGE_TILING_OPTIMAL, usage=usage,
        sharingMode=vk.VK_SHARING_MODE_EXCLUSIVE, initialLayout=vk.VK_IMAGE_LAYOUT_UNDEFINED,
    )
    handle = vk.vkCreateImage(ctx.device, info, None)
    owned.callback(vk.vkDestroyImage, ctx.device, handle, None)
    preferred = vk.VK_MEMORY_PROPERTY_LAZILY_ALLOCATED_BIT if lazy else 0
    memory = allocate(ctx, vk.vkGetImageMemoryRequirements(ctx.device, handle),
                      vk.VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, preferred)
    owned.callback(vk.vkFreeMemory, ctx.device, memory, None)
    vk.vkBindImageMemory(ctx.device, handle, memory, 0)
    view = create_view(ctx, owned, handle, vkf, aspect)
    return Image(handle, view, fmt, vkf, size, samples, aspect)


def create_view(ctx: VulkanContext, owned: ExitStack, image, vkf: int, aspect: int):
    """A 2D view with identity swizzle over the whole image."""
    identity = vk.VK_COMPONENT_SWIZZLE_IDENTITY
    info = vk.VkImageViewCreateInfo(
        image=image, viewType=vk.VK_IMAGE_VIEW_TYPE_2D, format=vkf,
        components=vk.VkComponentMapping(r=identity, g=identity, b=identity, a=identity),
        subresourceRange=subresource_range(aspect),
    )
    view = vk.vkCreateImageView(ctx.device, info, None)
    owned.callback(vk.vkDestroyImageView, ctx.device, view, None)
    return view


def transition(cmd, image: Image, old_layout: int, new_layout: int) -> None:
    """Record an image memory barrier from ``old_layout`` to ``new_layout``.

    The source scope is what wrote the image in its old layout (nothing for
    UNDEFINED, whose contents are discarded); the destination scope is what will
    access it in the new one. Queue family ownership does not change.
    """
    src_stage, src_access = LAYOUT_ACCESS[old_layout]
    dst_stage, dst_access = LAYOUT_ACCESS[new_layout]
    barrier = vk.VkImageMemoryBarrier(
        srcAccessMask=src_access, dstAccessMask=dst_access, oldLayout=old_layout, newLayout=new_layout,
        srcQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED, dstQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED,
        image=image.handle, subresourceRange=subresource_range(image.aspect),
    )
    vk.vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, None, 0, None, 1, [barrier])
