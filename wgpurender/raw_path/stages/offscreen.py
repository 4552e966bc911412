"""Course step 3a: render into an image of our own, then copy it to the output with vkCmdCopyImage.

The render pass leaves the offscreen image in TRANSFER_SRC_OPTIMAL (its
dependency to EXTERNAL orders the colour writes before the copy's reads); the
output goes UNDEFINED -> TRANSFER_DST_OPTIMAL for the copy, then
TRANSFER_DST_OPTIMAL -> TRANSFER_SRC_OPTIMAL for the readback, each by a barrier.
"""

from __future__ import annotations

import vulkan as vk

from wgpurender.core.course.triangle import BACKGROUND
from wgpurender.raw_path.device.images import Image, create_image, subresource_layers, transition
from wgpurender.raw_path.device.pipeline import set_viewport_and_scissor
from wgpurender.raw_path.stages.base import TARGET_LAYOUT, RefStage


class Offscreen(RefStage):
    name = "offscreen"
    summary = "render the triangle into an offscreen image, then copy it to the output"

    def setup(self) -> None:
        self.single_pass(BACKGROUND)
        self.pipeline = self.basic_pipeline("triangle.vert")
        usage = vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | vk.VK_IMAGE_USAGE_TRANSFER_SRC_BIT
        self.image = create_image(self.ctx, self.owned, self.size, self.format, usage)

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        self.begin_pass(cmd, self.image)  # the triangle into our own image
        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.pipeline)
        set_viewport_and_scissor(cmd, self.size)
        vk.vkCmdDraw(cmd, 3, 1, 0, 0)
        vk.vkCmdEndRenderPass(cmd)
        transition(cmd, target, TARGET_LAYOUT, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL)  # it arrives cleared
        origin = vk.VkOffset3D(x=0, y=0, z=0)
        region = vk.VkImageCopy(
            srcSubresource=subresource_layers(), srcOffset=origin,
            dstSubresource=subresource_layers(), dstOffset=origin,
            extent=vk.VkExtent3D(width=self.size[0], height=self.size[1], depth=1),
        )
        vk.vkCmdCopyImage(cmd, self.image.handle, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target.handle,
                          vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, [region])
        transition(cmd, target, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
