"""Course concepts: command pool, command buffers, fences, one-shot submits.

Commands are recorded into a VkCommandBuffer allocated from a VkCommandPool
(tied to one queue family), submitted with vkQueueSubmit, and the host waits for
them with a VkFence that the queue signals when the work is done. Everything
here is one-shot: begin with ONE_TIME_SUBMIT, record, end, submit, wait, free.
No semaphores: there is one queue and no swapchain, so no GPU-GPU waits between
submissions; the fence is the only host-GPU synchronisation.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import vulkan as vk

from wgpurender.raw_path.device.context import VulkanContext

FENCE_TIMEOUT_NS = 60 * 1_000_000_000  # lavapipe is slow but never this slow


def create_command_pool(ctx: VulkanContext):
    """TRANSIENT: its buffers are short-lived, a hint for the driver's allocator."""
    info = vk.VkCommandPoolCreateInfo(
        flags=vk.VK_COMMAND_POOL_CREATE_TRANSIENT_BIT, queueFamilyIndex=ctx.queue_family
    )
    return vk.vkCreateCommandPool(ctx.device, info, None)


def submit_and_wait(ctx: VulkanContext, cmd) -> None:
    """vkQueueSubmit with a fresh fence, then vkWaitForFences on the host."""
    fence = vk.vkCreateFence(ctx.device, vk.VkFenceCreateInfo(), None)
    try:
        submit = vk.VkSubmitInfo(pCommandBuffers=[cmd])
        vk.vkQueueSubmit(ctx.queue, 1, [submit], fence)
        vk.vkWaitForFences(ctx.device, 1, [fence], vk.VK_TRUE, FENCE_TIMEOUT_NS)
    finally:
        vk.vkDestroyFence(ctx.device, fence, None)


@contextmanager
def one_shot(ctx: VulkanContext) -> Iterator[object]:
    """Record into a primary command buffer; on exit, end it, submit it and wait for it."""
    pool = create_command_pool(ctx)
    try:
        alloc = vk.VkCommandBufferAllocateInfo(
            commandPool=pool, level=vk.VK_COMMAND_BUFFER_LEVEL_PRIMARY, commandBufferCount=1
        )
        cmd = vk.vkAllocateCommandBuffers(ctx.device, alloc)[0]
        begin = vk.VkCommandBufferBeginInfo(flags=vk.VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT)
        vk.vkBeginCommandBuffer(cmd, begin)  # initial -> recording
        yield cmd
        vk.vkEndCommandBuffer(cmd)  # recording -> executable
        submit_and_wait(ctx, cmd)  # executable -> pending -> (one-time) invalid
    finally:
        vk.vkDestroyCommandPool(ctx.device, pool, None)  # frees its command buffers too
