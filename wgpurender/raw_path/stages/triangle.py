"""Course step 2a: the first triangle in NDC, attribute-less (positions and colours from gl_VertexIndex).

One render pass, one subpass (with MSAA: a multisampled attachment resolved into
the target), a pipeline with no vertex input and an empty layout, and
vkCmdDraw(3). The viewport is flipped (see pipeline.set_viewport_and_scissor)
so that the y-up NDC positions give the same image as the wgpu stage.
shaders_glsl/triangle.vert holds the numbers (course/triangle.py has the same).
"""

from __future__ import annotations

import vulkan as vk

from wgpurender.core.course.triangle import BACKGROUND
from wgpurender.raw_path.device.images import Image
from wgpurender.raw_path.device.pipeline import set_viewport_and_scissor
from wgpurender.raw_path.stages.base import RefStage


class Triangle(RefStage):
    name = "triangle"
    summary = "first triangle, no vertex buffer: positions and colours from gl_VertexIndex"

    def setup(self) -> None:
        self.single_pass(BACKGROUND)
        self.pipeline = self.basic_pipeline("triangle.vert")

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        self.begin_pass(cmd, target)
        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.pipeline)
        set_viewport_and_scissor(cmd, self.size)
        vk.vkCmdDraw(cmd, 3, 1, 0, 0)
        vk.vkCmdEndRenderPass(cmd)
