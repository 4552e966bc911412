"""Course concepts: heaps and memory types, buffers, and staging uploads.

vkGetPhysicalDeviceMemoryProperties lists memory heaps (pools of bytes: VRAM,
system RAM) and memory types (a heap plus property flags: DEVICE_LOCAL,
HOST_VISIBLE, HOST_COHERENT, HOST_CACHED). A resource's VkMemoryRequirements
say which types it may live in (memoryTypeBits); we pick among those the first
type with all the *required* flags, trying first with the *preferred* flags too.

A staging upload writes the data into a HOST_VISIBLE buffer, then a transfer
command copies it into a DEVICE_LOCAL buffer that shaders read at full speed.
On lavapipe every type is both (it is all system memory); on a discrete GPU the
difference is the point.
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass

import numpy as np
import vulkan as vk

from wgpurender.core.errors import UserError
from wgpurender.raw_path.device.command_buffers import one_shot
from wgpurender.raw_path.device.context import VulkanContext

WHOLE_SIZE = 0xFFFFFFFFFFFFFFFF  # VK_WHOLE_SIZE; the binding's constant is -1, which does not fit a VkDeviceSize
HOST_MEMORY = vk.VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | vk.VK_MEMORY_PROPERTY_HOST_COHERENT_BIT


@dataclass
class Buffer:
    handle: object
    memory: object
    size: int


def find_memory_type(ctx: VulkanContext, type_bits: int, required: int, preferred: int = 0) -> int:
    """Index of a memory type allowed by ``type_bits`` with ``required`` flags, ``preferred`` ones if possible."""
    for wanted in (required | preferred, required):
        for index, memory_type in enumerate(ctx.memory_types):
            if type_bits & (1 << index) and memory_type.flags & wanted == wanted:
                return index
    raise UserError(f"no Vulkan memory type with flags {required:#x} for this resource (type bits {type_bits:#b})")


def allocate(ctx: VulkanContext, requirements, required: int, preferred: int = 0):
    """vkAllocateMemory of exactly what a resource asks for, from a suitable type."""
    index = find_memory_type(ctx, requirements.memoryTypeBits, required, preferred)
    info = vk.VkMemoryAllocateInfo(allocationSize=requirements.size, memoryTypeIndex=index)
    return vk.vkAllocateMemory(ctx.device, info, None)


def create_buffer(
    ctx: VulkanContext, owned: ExitStack, size: int, usage: int, required: int, preferred: int = 0
) -> Buffer:
    """A VkBuffer with its own VkDeviceMemory, both destroyed when ``owned`` closes."""
    info = vk.VkBufferCreateInfo(size=size, usage=usage, sharingMode=vk.VK_SHARING_MODE_EXCLUSIVE)
    handle = vk.vkCreateBuffer(ctx.device, info, None)
    owned.callback(vk.vkDestroyBuffer, ctx.device, handle, None)
    memory = allocate(ctx, vk.vkGetBufferMemoryRequirements(ctx.device, handle), required, preferred)
    owned.callback(vk.vkFreeMemory, ctx.device, memory, None)
    vk.vkBindBufferMemory(ctx.device, handle, memory, 0)
    return Buffer(handle, memory, size)


def write_host_buffer(ctx: VulkanContext, buffer: Buffer, data: np.ndarray | bytes) -> None:
    """Map, copy, unmap. HOST_COHERENT memory needs no vkFlushMappedMemoryRanges."""
    raw = np.frombuffer(data, np.uint8) if isinstance(data, bytes) else np.ascontiguousarray(data).view(np.uint8)
    raw = raw.reshape(-1)
    mapped = vk.vkMapMemory(ctx.device, buffer.memory, 0, raw.nbytes, 0)
    vk.ffi.memmove(mapped, raw, raw.nbytes)
    vk.vkUnmapMemory(ctx.device, buffer.memory)


def read_host_buffer(ctx: VulkanContext, buffer: Buffer) -> np.ndarray:
    mapped = vk.vkMapMemory(ctx.device, buffer.memory, 0, buffer.size, 0)
    data = np.frombuffer(mapped, dtype=np.uint8).copy()
    vk.vkUnmapMemory(ctx.device, buffer.memory)
    return data


def upload_buffer(ctx: VulkanContext, owned: ExitStack, data: np.ndarray, usage: int, reader_stage: int,
                  reader_access: int) -> Buffer:
    """A DEVICE_LOCAL buffer filled through a staging buffer and vkCmdCopyBuffer.

    The buffer memory barrier makes the transfer write available and visible to
    the later reader (e.g. VERTEX_INPUT stage, VERTEX_ATTRIBUTE_READ access).
    """
    raw = np.ascontiguousarray(data)
    with ExitStack() as staging_owned:  # the staging buffer lives only until the copy is done
        staging = create_buffer(ctx, staging_owned, raw.nbytes, vk.VK_BUFFER_USAGE_TRANSFER_SRC_BIT, HOST_MEMORY)
        write_host_buffer(ctx, staging, raw)
        target = create_buffer(ctx, owned, raw.nbytes, usage | vk.VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               vk.VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)
        with one_shot(ctx) as cmd:
            record_copy(cmd, staging, target, raw.nbytes, reader_stage, reader_access)
    return target


def record_copy(cmd, source: Buffer, target: Buffer, size: int, reader_stage: int, reader_access: int,
                offset: int = 0) -> None:
    """vkCmdCopyBuffer of ``size`` bytes from ``offset`` (the same in both buffers), then the barrier that makes
    the write visible to the later reader."""
    region = vk.VkBufferCopy(srcOffset=offset, dstOffset=offset, size=size)
    vk.vkCmdCopyBuffer(cmd, source.handle, target.handle, 1, [region])
    barrier = vk.VkBufferMemoryBarrier(
        srcAccessMask=vk.VK_ACCESS_TRANSFER_WRITE_BIT, dstAccessMask=reader_access,
        srcQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED, dstQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED,
        buffer=target.handle, offset=0, size=WHOLE_SIZE,
    )
    vk.vkCmdPipelineBarrier(cmd, vk.VK_PIPELINE_STAGE_TRANSFER_BIT, reader_stage, 0, 0, None, 1, [barrier], 0, None)
