"""Course step 1b: clear with a render pass whose colour attachment has load_op "clear".

This is vkCmdBeginRenderPass with a VkClearValue and loadOp CLEAR, then an empty
pass: the clear happens when the attachment is loaded.
"""

from __future__ import annotations

import wgpu

from .base import Stage

# A colour that is exact in every format: 0, 1 and 0.5 (0.5 is 128/255 only after rounding, so
# we pick values k/255 that survive the float -> unorm conversion exactly).
CLEAR_COLOR = (51 / 255, 102 / 255, 204 / 255, 1.0)


class ClearPass(Stage):
    name = "clear-pass"
    summary = "clear the image through a render pass (load_op clear) and draw nothing"
    course_step = "1b: clear with a render pass (loadOp CLEAR, VkClearValue)"
    order = 1.1
    clear_color = CLEAR_COLOR

    def draw(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, self.clear_color)])
        render_pass.end()
