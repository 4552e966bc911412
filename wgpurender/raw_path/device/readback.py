"""Course concept: offscreen readback with vkCmdCopyImageToBuffer.

The rendered image (in TRANSFER_SRC_OPTIMAL) is copied into a HOST_VISIBLE
buffer, tightly packed (bufferRowLength 0: Vulkan has no row-alignment rule for
this copy, unlike WebGPU's 256 bytes). A buffer barrier makes the transfer
write visible to host reads; once the fence has signalled, the host maps the
memory. HOST_CACHED is preferred: reading uncached memory from the CPU is slow.
"""

from __future__ import annotations

from contextlib import ExitStack

import numpy as np
import vulkan as vk

from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.images import FORMATS, Image, subresource_layers
from wgpurender.raw_path.device.memory import HOST_MEMORY, WHOLE_SIZE, Buffer, create_buffer, read_host_buffer


def record_copy_to_buffer(ctx: VulkanContext, owned: ExitStack, cmd, image: Image) -> Buffer:
    """Record the copy of a single-sample image in TRANSFER_SRC_OPTIMAL; returns the buffer it lands in."""
    width, height = image.size
    size = width * height * FORMATS[image.format][1]
    buffer = create_buffer(ctx, owned, size, vk.VK_BUFFER_USAGE_TRANSFER_DST_BIT, HOST_MEMORY,
                           vk.VK_MEMORY_PROPERTY_HOST_CACHED_BIT)
    region = vk.VkBufferImageCopy(
        bufferOffset=0, bufferRowLength=0, bufferImageHeight=0, imageSubresource=subresource_layers(),
        imageOffset=vk.VkOffset3D(x=0, y=0, z=0), imageExtent=vk.VkExtent3D(width=width, height=height, depth=1),
    )
    vk.vkCmdCopyImageToBuffer(cmd, image.handle, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.handle, 1, [region])
    barrier = vk.VkBufferMemoryBarrier(
        srcAccessMask=vk.VK_ACCESS_TRANSFER_WRITE_BIT, dstAccessMask=vk.VK_ACCESS_HOST_READ_BIT,
        srcQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED, dstQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED,
        buffer=buffer.handle, offset=0, size=WHOLE_SIZE,
    )
    vk.vkCmdPipelineBarrier(cmd, vk.VK_PIPELINE_STAGE_TRANSFER_BIT, vk.VK_PIPELINE_STAGE_HOST_BIT, 0, 0, None, 1,
                            [barrier], 0, None)
    return buffer


def buffer_to_pixels(ctx: VulkanContext, buffer: Buffer, image: Image) -> np.ndarray:
    """(H, W, 4) pixels: uint8 for 8-bit formats (stored bytes, so sRGB-encoded for -srgb), float16 for rgba16float."""
    width, height = image.size
    dtype = FORMATS[image.format][2]
    return read_host_buffer(ctx, buffer).view(dtype).reshape(height, width, 4)
