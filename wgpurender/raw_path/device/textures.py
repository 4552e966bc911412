"""Course concepts: a sampled texture (staging upload, a mip chain, layout transitions) and VkSampler.

The course's sequence, spelled out:
1. the pixels go into a HOST_VISIBLE staging buffer (memory.create_buffer + a mapped write);
2. level 0 moves UNDEFINED -> TRANSFER_DST_OPTIMAL (a barrier), vkCmdCopyBufferToImage fills
   it, and it moves TRANSFER_DST_OPTIMAL -> SHADER_READ_ONLY_OPTIMAL (a barrier whose source
   scope is the copy's transfer write and whose destination scope is fragment-shader reads);
3. every further level i is drawn by a render pass that reads level i-1 (a one-level view,
   a SAMPLED_IMAGE descriptor) and writes level i (a one-level view as colour attachment).
   The render pass takes level i from UNDEFINED to COLOR_ATTACHMENT_OPTIMAL on entry and to
   SHADER_READ_ONLY_OPTIMAL on exit; its dependency to EXTERNAL makes the writes visible
   to the next pass's fragment shader, which reads that level;
4. a VkSampler per filter setting; anisotropy needs the samplerAnisotropy device feature
   (instance.create_device enables it when the device offers it).

The course fills the levels with vkCmdBlitImage (level i-1 -> level i with VK_FILTER_LINEAR,
a TRANSFER_SRC/TRANSFER_DST barrier pair per level). We do not use the blit here: its filter is
the driver's bilinear resampling, which for odd sizes skips or blurs source texels, and it
averages the stored sRGB bytes on some drivers. The wgpu path (wgpurender/wgpu_path/device/textures.py,
shaders_wgsl/mipmap.wgsl) uses an exact area-weighted box filter in linear light; the raw
path must use the same filter for the two images to be compared, so
shaders_glsl/textured_mipmap.frag does the same integer-weight arithmetic in GLSL.
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass

import numpy as np
import vulkan as vk

from wgpurender.raw_path.device import descriptors
from wgpurender.raw_path.device.command_buffers import one_shot
from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.images import LAYOUT_ACCESS, Image, transition
from wgpurender.raw_path.device.memory import (
    HOST_MEMORY,
    WHOLE_SIZE,
    allocate,
    create_buffer,
    read_host_buffer,
    write_host_buffer,
)
from wgpurender.raw_path.device.pipeline import (
    PipelineDesc,
    create_pipeline,
    create_pipeline_layout,
    set_viewport_and_scissor,
)
from wgpurender.raw_path.device.renderpass import (
    attachment,
    begin,
    create_framebuffer,
    create_render_pass,
    dependency,
    into_pass,
    ref,
)

READ_ONLY = vk.VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL
TEXTURE_FORMATS = {True: vk.VK_FORMAT_R8G8B8A8_SRGB, False: vk.VK_FORMAT_R8G8B8A8_UNORM}
# TRANSFER_SRC only for read_level (tests); wgpu's texture has COPY_SRC too.
TEXTURE_USAGE = (
    vk.VK_IMAGE_USAGE_SAMPLED_BIT | vk.VK_IMAGE_USAGE_TRANSFER_DST_BIT | vk.VK_IMAGE_USAGE_TRANSFER_SRC_BIT
    | vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT
)
MIPMAP_SHADERS = ("fullscreen.vert", "textured_mipmap.frag")

FILTERS = {"nearest": vk.VK_FILTER_NEAREST, "linear": vk.VK_FILTER_LINEAR}
MIPMAP_MODES = {"nearest": vk.VK_SAMPLER_MIPMAP_MODE_NEAREST, "linear": vk.VK_SAMPLER_MIPMAP_MODE_LINEAR}
ADDRESS_MODES = {
    "repeat": vk.VK_SAMPLER_ADDRESS_MODE_REPEAT,
    "clamp-to-edge": vk.VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
    "mirror-repeat": vk.VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT,
}


@dataclass
class TextureImage:
    """A sampled 2D image with its mip chain: the view of all levels, and one view per level."""

    handle: object
    view: object
    level_views: list
    size: tuple[int, int]
    vk_format: int
    levels: int

    def level(self, i: int) -> Image:
        """Level ``i`` as an :class:`Image` (its own view and size), for framebuffers and transitions."""
        return Image(self.handle, self.level_views[i], "", self.vk_format, level_size(self.size, i), 1,
                     vk.VK_IMAGE_ASPECT_COLOR_BIT)


def level_count(size: tuple[int, int]) -> int:
    """floor(log2(largest side)) + 1: down to 1x1."""
    return max(size).bit_length()


def level_size(size: tuple[int, int], level: int) -> tuple[int, int]:
    return max(1, size[0] >> level), max(1, size[1] >> level)


def level_range(base: int, count: int):
    """VkImageSubresourceRange of ``count`` mip levels from ``base`` (colour, layer 0)."""
    return vk.VkImageSubresourceRange(aspectMask=vk.VK_IMAGE_ASPECT_COLOR_BIT, baseMipLevel=base,
                                      levelCount=count, baseArrayLayer=0, layerCount=1)


def level_layers(level: int):
    """VkImageSubresourceLayers: how copy commands name one mip level (colour, layer 0)."""
    return vk.VkImageSubresourceLayers(aspectMask=vk.VK_IMAGE_ASPECT_COLOR_BIT, mipLevel=level, baseArrayLayer=0,
                                       layerCount=1)


def _view(ctx: VulkanContext, owned: ExitStack, image, vkf: int, base: int, count: int):
    identity = vk.VK_COMPONENT_SWIZZLE_IDENTITY
    info = vk.VkImageViewCreateInfo(
        image=image, viewType=vk.VK_IMAGE_VIEW_TYPE_2D, format=vkf,
        components=vk.VkComponentMapping(r=identity, g=identity, b=identity, a=identity),
        subresourceRange=level_range(base, count),
    )
    view = vk.vkCreateImageView(ctx.device, info, None)
    owned.callback(vk.vkDestroyImageView, ctx.device, view, None)
    return view


def create_texture_image(ctx: VulkanContext, owned: ExitStack, size: tuple[int, int], srgb: bool,
                         mips: bool = True) -> TextureImage:
    """A DEVICE_LOCAL RGBA8 image with a full mip chain (or one level), its views, destroyed with ``owned``."""
    vkf = TEXTURE_FORMATS[srgb]
    levels = level_count(size) if mips else 1
    info = vk.VkImageCreateInfo(
        imageType=vk.VK_IMAGE_TYPE_2D, format=vkf, extent=vk.VkExtent3D(width=size[0], height=size[1], depth=1),
        mipLevels=levels, arrayLayers=1, samples=vk.VK_SAMPLE_COUNT_1_BIT, tiling=vk.VK_IMAGE_TILING_OPTIMAL,
        usage=TEXTURE_USAGE, sharingMode=vk.VK_SHARING_MODE_EXCLUSIVE, initialLayout=vk.VK_IMAGE_LAYOUT_UNDEFINED,
    )
    handle = vk.vkCreateImage(ctx.device, info, None)
    owned.callback(vk.vkDestroyImage, ctx.device, handle, None)
    memory = allocate(ctx, vk.vkGetImageMemoryRequirements(ctx.device, handle), vk.VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)
    owned.callback(vk.vkFreeMemory, ctx.device, memory, None)
    vk.vkBindImageMemory(ctx.device, handle, memory, 0)
    view = _view(ctx, owned, handle, vkf, 0, levels)
    level_views = [_view(ctx, owned, handle, vkf, i, 1) for i in range(levels)]
    return TextureImage(handle, view, level_views, size, vkf, levels)


def record_upload(cmd, texture: TextureImage, staging) -> None:
    """Level 0 from the staging buffer: transition, vkCmdCopyBufferToImage (rows tightly packed), transition."""
    level0 = texture.level(0)
    transition(cmd, level0, vk.VK_IMAGE_LAYOUT_UNDEFINED, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL)
    region = vk.VkBufferImageCopy(
        bufferOffset=0, bufferRowLength=0, bufferImageHeight=0,
        imageSubresource=level_layers(0),
        imageOffset=vk.VkOffset3D(x=0, y=0, z=0),
        imageExtent=vk.VkExtent3D(width=texture.size[0], height=texture.size[1], depth=1),
    )
    vk.vkCmdCopyBufferToImage(cmd, staging.handle, texture.handle, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                              [region])
    transition(cmd, level0, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, READ_ONLY)


class MipGenerator:
    """The render pass, set layout and pipeline that draw one mip level from the previous one."""

    def __init__(self, ctx: VulkanContext, owned: ExitStack, vk_format: int) -> None:
        self.ctx, self.owned = ctx, owned
        # The level is fully overwritten by the full-screen triangle: nothing to load.
        color = attachment(vk_format, 1, vk.VK_ATTACHMENT_LOAD_OP_DONT_CARE, vk.VK_ATTACHMENT_STORE_OP_STORE,
                           READ_ONLY)
        subpass = vk.VkSubpassDescription(pipelineBindPoint=vk.VK_PIPELINE_BIND_POINT_GRAPHICS,
                                          pColorAttachments=[ref(0)])
        to_next_level = dependency(0, vk.VK_SUBPASS_EXTERNAL, vk.VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                   vk.VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, vk.VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                                   vk.VK_ACCESS_SHADER_READ_BIT)
        self.render_pass = create_render_pass(ctx, owned, [color], [subpass], [into_pass(), to_next_level], [])
        self.bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, vk.VK_SHADER_STAGE_FRAGMENT_BIT)]
        self.set_layout = descriptors.create_set_layout(ctx, owned, self.bindings)
        self.layout = create_pipeline_layout(ctx, owned, [self.set_layout])
        self.pipeline = create_pipeline(ctx, owned, PipelineDesc(*MIPMAP_SHADERS), self.layout, self.render_pass)

    def record(self, cmd, texture: TextureImage) -> None:
        """Levels 1.. from level 0, which must already be in SHADER_READ_ONLY_OPTIMAL."""
        if texture.levels == 1:
            return
        ctx, owned = self.ctx, self.owned
        pool = descriptors.create_pool(ctx, owned, [self.bindings] * (texture.levels - 1))
        sources = descriptors.allocate_sets(ctx, pool, [self.set_layout] * (texture.levels - 1))
        descriptors.update(ctx, [
            descriptors.write_image(s, 0, texture.level_views[i], READ_ONLY, vk.VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE)
            for i, s in enumerate(sources)
        ])
        for level in range(1, texture.levels):
            target = texture.level(level)
            framebuffer = create_framebuffer(ctx, owned, self.render_pass, [target])
            begin(cmd, self.render_pass, framebuffer, target.size)
            vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.pipeline)
            set_viewport_and_scissor(cmd, target.size)
            vk.vkCmdBindDescriptorSets(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.layout, 0, 1,
                                       [sources[level - 1]], 0, None)
            vk.vkCmdDraw(cmd, 3, 1, 0, 0)
            vk.vkCmdEndRenderPass(cmd)


def upload_texture(ctx: VulkanContext, owned: ExitStack, pixels: np.ndarray, srgb: bool,
                   mips: bool = True) -> TextureImage:
    """(H, W, 4) uint8 pixels -> a sampled texture with its mip chain, every level in SHADER_READ_ONLY_OPTIMAL.

    One command buffer: the upload of level 0, then one render pass per further level.
    The staging buffer is freed once the fence says the copy is done.
    """
    raw = np.ascontiguousarray(pixels, dtype=np.uint8)
    height, width = raw.shape[:2]
    texture = create_texture_image(ctx, owned, (width, height), srgb, mips)
    generator = MipGenerator(ctx, owned, texture.vk_format) if texture.levels > 1 else None
    with ExitStack() as staging_owned:
        staging = create_buffer(ctx, staging_owned, raw.nbytes, vk.VK_BUFFER_USAGE_TRANSFER_SRC_BIT, HOST_MEMORY)
        write_host_buffer(ctx, staging, raw)
        with one_shot(ctx) as cmd:
            record_upload(cmd, texture, staging)
            if generator is not None:
                generator.record(cmd, texture)
    return texture


def transition_level(cmd, texture: TextureImage, level: int, old_layout: int, new_layout: int) -> None:
    """images.transition for one mip level (that one always names level 0)."""
    src_stage, src_access = LAYOUT_ACCESS[old_layout]
    dst_stage, dst_access = LAYOUT_ACCESS[new_layout]
    barrier = vk.VkImageMemoryBarrier(
        srcAccessMask=src_access, dstAccessMask=dst_access, oldLayout=old_layout, newLayout=new_layout,
        srcQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED, dstQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED,
        image=texture.handle, subresourceRange=level_range(level, 1),
    )
    vk.vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, None, 0, None, 1, [barrier])


def read_level(ctx: VulkanContext, texture: TextureImage, level: int) -> np.ndarray:
    """One mip level as (h, w, 4) uint8 stored bytes (tests): out of SHADER_READ_ONLY, copied, and back."""
    width, height = level_size(texture.size, level)
    with ExitStack() as owned:
        buffer = create_buffer(ctx, owned, width * height * 4, vk.VK_BUFFER_USAGE_TRANSFER_DST_BIT, HOST_MEMORY,
                               vk.VK_MEMORY_PROPERTY_HOST_CACHED_BIT)
        with one_shot(ctx) as cmd:
            transition_level(cmd, texture, level, READ_ONLY, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
            region = vk.VkBufferImageCopy(
                bufferOffset=0, bufferRowLength=0, bufferImageHeight=0,
                imageSubresource=level_layers(level), imageOffset=vk.VkOffset3D(x=0, y=0, z=0),
                imageExtent=vk.VkExtent3D(width=width, height=height, depth=1),
            )
            vk.vkCmdCopyImageToBuffer(cmd, texture.handle, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.handle, 1,
                                      [region])
            host = vk.VkBufferMemoryBarrier(
                srcAccessMask=vk.VK_ACCESS_TRANSFER_WRITE_BIT, dstAccessMask=vk.VK_ACCESS_HOST_READ_BIT,
                srcQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED, dstQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED,
                buffer=buffer.handle, offset=0, size=WHOLE_SIZE,
            )
            vk.vkCmdPipelineBarrier(cmd, vk.VK_PIPELINE_STAGE_TRANSFER_BIT, vk.VK_PIPELINE_STAGE_HOST_BIT, 0, 0, None,
                                    1, [host], 0, None)
            transition_level(cmd, texture, level, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, READ_ONLY)
        return read_host_buffer(ctx, buffer).reshape(height, width, 4)


def sampler_info(spec, anisotropy_supported: bool = True):
    """VkSamplerCreateInfo for a wgpu_path.device.textures.SamplerSpec, field for field as wgpu's Vulkan backend
    fills it.

    mipLodBias 0, no compare, border colour unused (no clamp-to-border). Anisotropy is
    enabled only for max_anisotropy > 1 and only where the device supports it (wgpu
    clamps it to 1 otherwise); the spec already guarantees linear filters then.
    """
    info = vk.VkSamplerCreateInfo(
        magFilter=FILTERS[spec.mag_filter], minFilter=FILTERS[spec.min_filter],
        mipmapMode=MIPMAP_MODES[spec.mipmap_filter],
        addressModeU=ADDRESS_MODES[spec.address_mode_u], addressModeV=ADDRESS_MODES[spec.address_mode_v],
        addressModeW=ADDRESS_MODES[spec.address_mode_w],
        mipLodBias=0.0, minLod=float(spec.lod_min_clamp), maxLod=float(spec.lod_max_clamp),
    )
    if spec.max_anisotropy > 1 and anisotropy_supported:
        info.anisotropyEnable = vk.VK_TRUE
        info.maxAnisotropy = float(spec.max_anisotropy)
    return info


def anisotropy_supported(ctx: VulkanContext) -> bool:
    """The samplerAnisotropy feature: create_device enables it exactly when this is true."""
    return bool(vk.vkGetPhysicalDeviceFeatures(ctx.physical_device).samplerAnisotropy)


def create_sampler(ctx: VulkanContext, owned: ExitStack, spec):
    """vkCreateSampler for a SamplerSpec (filters, mipmap mode, address modes, LOD clamps, anisotropy)."""
    sampler = vk.vkCreateSampler(ctx.device, sampler_info(spec, anisotropy_supported(ctx)), None)
    owned.callback(vk.vkDestroySampler, ctx.device, sampler, None)
    return sampler
