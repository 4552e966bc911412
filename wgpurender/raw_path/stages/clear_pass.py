"""Course step 1b: clear with a render pass: loadOp CLEAR and a VkClearValue, no draw.

The clear happens when the render pass loads the attachment; the pass's final
layout (TRANSFER_SRC_OPTIMAL) and its dependency to EXTERNAL hand the image to
the readback copy.
"""

from __future__ import annotations

import vulkan as vk

from wgpurender.core.course.triangle import CLEAR_COLOR  # exact in every format
from wgpurender.raw_path.device.images import Image
from wgpurender.raw_path.device.renderpass import begin, create_framebuffer, single_pass
from wgpurender.raw_path.stages.base import RefStage


class ClearPass(RefStage):
    name = "clear-pass"
    summary = "clear the image through a render pass (loadOp CLEAR) and draw nothing"

    def setup(self) -> None:
        self.render_pass = single_pass(self.ctx, self.owned, self.format, 1, CLEAR_COLOR)

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        framebuffer = create_framebuffer(self.ctx, self.owned, self.render_pass, [target])
        begin(cmd, self.render_pass, framebuffer, self.size)
        vk.vkCmdEndRenderPass(cmd)
