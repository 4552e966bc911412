"""The raw-Vulkan peer of the frame benchmarks: a raw stage drawn into one image, frame after frame
(wgpurender/bench/frames.py measures it beside the wgpu stage).

Its own module, free of wgpu: the startup family's raw child imports it to time the raw path's first pixel,
and importing wgpu-py there (as bench/frames.py does) added wgpu-py's import to the raw path's time.
"""

from __future__ import annotations

import time
from contextlib import ExitStack


class RawStageRunner:
    """A raw-Vulkan stage drawn into one image, frame after frame, with one command buffer and fence reused."""

    def __init__(self, name: str, size: tuple[int, int], fmt: str | None = None, msaa: int | None = None) -> None:
        from wgpurender.raw_path.device.checks import check_msaa, check_size
        from wgpurender.raw_path.device.context import get_vulkan
        from wgpurender.raw_path.stages import get_ref_stage

        ctx = get_vulkan()
        cls = get_ref_stage(name)
        self.name = name
        self.size = check_size(ctx, size)
        self.owned = ExitStack()
        self.stage = cls(ctx, self.owned, fmt or cls.default_format, check_msaa(ctx, cls, msaa), self.size)
        self._setup_frames(ctx, self.stage.format)

    def _setup_frames(self, ctx, fmt: str) -> None:
        """The target image, one command buffer, a fence and a timestamp pool, reused every frame."""
        import vulkan as vk

        from wgpurender.raw_path.device.command_buffers import create_command_pool
        from wgpurender.raw_path.device.images import create_image, transition
        from wgpurender.raw_path.stages.base import TARGET_LAYOUT, TARGET_USAGE

        self.vk, self.ctx, self.format = vk, ctx, fmt
        self.into_target_layout, self.target_layout = transition, TARGET_LAYOUT  # where a stage's barriers start
        owned = self.owned
        self.target = create_image(ctx, owned, self.size, fmt, TARGET_USAGE)
        self.pool = create_command_pool(ctx)
        owned.callback(vk.vkDestroyCommandPool, ctx.device, self.pool, None)
        alloc = vk.VkCommandBufferAllocateInfo(commandPool=self.pool, level=vk.VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                               commandBufferCount=1)
        self.cmd = vk.vkAllocateCommandBuffers(ctx.device, alloc)[0]
        self.fence = vk.vkCreateFence(ctx.device, vk.VkFenceCreateInfo(), None)
        owned.callback(vk.vkDestroyFence, ctx.device, self.fence, None)
        self.queries = vk.vkCreateQueryPool(
            ctx.device, vk.VkQueryPoolCreateInfo(queryType=vk.VK_QUERY_TYPE_TIMESTAMP, queryCount=2), None)
        owned.callback(vk.vkDestroyQueryPool, ctx.device, self.queries, None)
        self.period_ns = float(vk.vkGetPhysicalDeviceProperties(ctx.physical_device).limits.timestampPeriod)
        self._ticks = vk.ffi.new("uint64_t[2]")
        self._readback = None
        self.t = 0.0

    def close(self) -> None:
        self.vk.vkDeviceWaitIdle(self.ctx.device)
        self.owned.close()
        self.ctx.check_validation(f"the raw-Vulkan benchmark of {self.name!r}")

    def __enter__(self) -> RawStageRunner:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _readback_buffer(self):
        if self._readback is None:
            from wgpurender.raw_path.device.images import FORMATS
            from wgpurender.raw_path.device.memory import HOST_MEMORY, create_buffer

            vk = self.vk
            nbytes = self.size[0] * self.size[1] * FORMATS[self.format][1]
            self._readback = create_buffer(self.ctx, self.owned, nbytes, vk.VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           HOST_MEMORY, vk.VK_MEMORY_PROPERTY_HOST_CACHED_BIT)
        return self._readback

    def _record_copy(self, cmd) -> None:
        """vkCmdCopyImageToBuffer into the reused host buffer + a barrier for the host read."""
        from wgpurender.raw_path.device.images import subresource_layers
        from wgpurender.raw_path.device.memory import WHOLE_SIZE

        vk, buffer = self.vk, self._readback_buffer()
        region = vk.VkBufferImageCopy(
            bufferOffset=0, bufferRowLength=0, bufferImageHeight=0, imageSubresource=subresource_layers(),
            imageOffset=vk.VkOffset3D(x=0, y=0, z=0),
            imageExtent=vk.VkExtent3D(width=self.size[0], height=self.size[1], depth=1))
        vk.vkCmdCopyImageToBuffer(cmd, self.target.handle, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.handle, 1,
                                  [region])
        barrier = vk.VkBufferMemoryBarrier(
            srcAccessMask=vk.VK_ACCESS_TRANSFER_WRITE_BIT, dstAccessMask=vk.VK_ACCESS_HOST_READ_BIT,
            srcQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED, dstQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED,
            buffer=buffer.handle, offset=0, size=WHOLE_SIZE)
        vk.vkCmdPipelineBarrier(cmd, vk.VK_PIPELINE_STAGE_TRANSFER_BIT, vk.VK_PIPELINE_STAGE_HOST_BIT, 0, 0, None, 1,
                                [barrier], 0, None)

    def frame(self, readback: bool = False) -> tuple[float, float]:
        vk, ctx, cmd = self.vk, self.ctx, self.cmd
        start = time.perf_counter()
        vk.vkResetCommandPool(ctx.device, self.pool, 0)
        vk.vkBeginCommandBuffer(cmd, vk.VkCommandBufferBeginInfo(flags=vk.VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT))
        vk.vkCmdResetQueryPool(cmd, self.queries, 0, 2)
        vk.vkCmdWriteTimestamp(cmd, vk.VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, self.queries, 0)
        self.into_target_layout(cmd, self.target, vk.VK_IMAGE_LAYOUT_UNDEFINED, self.target_layout)
        self.stage.record(cmd, self.target, self.t)
        vk.vkCmdWriteTimestamp(cmd, vk.VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, self.queries, 1)
        if readback:
            self._record_copy(cmd)
        vk.vkEndCommandBuffer(cmd)
        submit = vk.VkSubmitInfo(pCommandBuffers=[cmd])
        vk.vkQueueSubmit(ctx.queue, 1, [submit], self.fence)
        cpu_ms = (time.perf_counter() - start) * 1e3
        vk.vkWaitForFences(ctx.device, 1, [self.fence], vk.VK_TRUE, 60 * 10**9)
        vk.vkResetFences(ctx.device, 1, [self.fence])
        vk.lib.vkGetQueryPoolResults(ctx.device, self.queries, 0, 2, 16, self._ticks, 8,
                                     vk.VK_QUERY_RESULT_64_BIT | vk.VK_QUERY_RESULT_WAIT_BIT)
        gpu_ms = (int(self._ticks[1]) - int(self._ticks[0])) * self.period_ns / 1e6
        if readback:
            from wgpurender.raw_path.device.memory import read_host_buffer

            read_host_buffer(ctx, self._readback)
        return cpu_ms, gpu_ms
