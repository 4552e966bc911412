"""Course step 1a: clear an image without a render pass: vkCmdClearColorImage.

A transfer command: the image goes to TRANSFER_DST_OPTIMAL (a barrier), is
cleared, and goes to TRANSFER_SRC_OPTIMAL for the readback (another barrier,
whose source scope is the clear's transfer write).

The colour: vkCmdClearColorImage takes any colour, but the wgpu 'clear' stage can
only clear to zero (WebGPU's clear_texture has no colour argument), so this stage
clears to (0, 0, 0, 0) as well, so that the two can be compared. ``color`` is a
class attribute: a test clears to the clear-pass colour to check the pass-less
and the render-pass clear agree.
"""

from __future__ import annotations

import vulkan as vk

from wgpurender.core.course.triangle import TRANSFER_CLEAR_COLOR
from wgpurender.raw_path.device.images import Image, subresource_range, transition
from wgpurender.raw_path.stages.base import TARGET_LAYOUT, RefStage


class ClearTransfer(RefStage):
    name = "clear"
    summary = "clear the image with vkCmdClearColorImage, no render pass (to zero, like the wgpu stage)"
    color = TRANSFER_CLEAR_COLOR

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        transition(cmd, target, TARGET_LAYOUT, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL)  # it arrives cleared
        color = vk.VkClearColorValue(float32=list(self.color))
        ranges = [subresource_range()]
        vk.vkCmdClearColorImage(cmd, target.handle, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, color, 1, ranges)
        transition(cmd, target, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
