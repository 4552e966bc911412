"""Course step 1b: clear with a render pass whose colour attachment has load_op "clear".

This is vkCmdBeginRenderPass with a VkClearValue and loadOp CLEAR, then an empty
pass: the clear happens when the attachment is loaded. The colour
(course/triangle.py's CLEAR_COLOR) is exact in every format.
"""

from __future__ import annotations

import wgpu

from wgpurender.core.course.triangle import CLEAR_COLOR
from wgpurender.wgpu_path.stages.base import Stage


class ClearPass(Stage):
    name = "clear-pass"
    summary = "clear the image through a render pass (load_op clear) and draw nothing"
    clear_color = CLEAR_COLOR

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, self.clear_color)])
        render_pass.end()
