"""Course step 2a: the first triangle in NDC, attribute-less (positions and colours from gl_VertexIndex).

One render pass, one subpass (with MSAA: a multisampled attachment resolved into
the target), a pipeline with no vertex input and an empty layout, and
vkCmdDraw(3). The viewport is flipped (see pipeline.set_viewport_and_scissor)
so that the y-up NDC positions give the same image as the wgpu stage.
"""

from __future__ import annotations

import numpy as np
import vulkan as vk

from ..images import Image
from ..pipeline import PipelineDesc, create_pipeline, create_pipeline_layout, set_viewport_and_scissor
from ..renderpass import begin, create_framebuffer, single_pass
from .base import RefStage

# The same numbers as shaders_glsl/triangle.vert, kept here independently of the wgpu path's copy
# (NDC, y up; linear RGB), so that a change on either side shows up as a failing comparison.
TRIANGLE_POSITIONS = np.array([[-0.8, -0.7], [0.7, -0.5], [-0.1, 0.8]], dtype=np.float32)
TRIANGLE_COLORS = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
BACKGROUND = (0.0, 0.0, 0.0, 1.0)


class Triangle(RefStage):
    name = "triangle"
    summary = "first triangle, no vertex buffer: positions and colours from gl_VertexIndex"
    order = 2.0
    supports_msaa = True
    vertex_shader = "triangle.vert"

    def setup(self) -> None:
        self.render_pass = single_pass(self.ctx, self.owned, self.format, self.msaa, BACKGROUND)
        self.layout = create_pipeline_layout(self.ctx, self.owned)
        self.pipeline = create_pipeline(self.ctx, self.owned, self.pipeline_desc(), self.layout, self.render_pass)
        self.msaa_image = self.transient_msaa_image() if self.msaa > 1 else None

    def pipeline_desc(self) -> PipelineDesc:
        return PipelineDesc(vert=self.vertex_shader, frag="color.frag", samples=self.msaa)

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        views = [target] if self.msaa_image is None else [self.msaa_image, target]
        framebuffer = create_framebuffer(self.ctx, self.owned, self.render_pass, views)
        begin(cmd, self.render_pass, framebuffer, self.size)
        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.pipeline)
        set_viewport_and_scissor(cmd, self.size)
        self.draw(cmd)
        vk.vkCmdEndRenderPass(cmd)

    def draw(self, cmd) -> None:
        vk.vkCmdDraw(cmd, 3, 1, 0, 0)
