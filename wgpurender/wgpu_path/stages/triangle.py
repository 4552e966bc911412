"""Course step 2a: the first triangle in NDC, attribute-less (everything from the vertex index).

shaders_wgsl/triangle.wgsl holds the positions and colours (course/triangle.py has the same numbers).
"""

from __future__ import annotations

import wgpu

from wgpurender.core.course.triangle import BACKGROUND
from wgpurender.wgpu_path.stages.base import Stage


class Triangle(Stage):
    name = "triangle"
    summary = "first triangle, no vertex buffer: positions and colours from the vertex index"

    def setup(self) -> None:
        self.pipeline = self.basic_pipeline("triangle.wgsl")

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, BACKGROUND)])
        render_pass.set_pipeline(self.pipeline)
        render_pass.draw(3)
        render_pass.end()
