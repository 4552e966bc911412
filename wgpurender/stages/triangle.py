"""Course step 2a: the first triangle in NDC, attribute-less (everything from the vertex index)."""

from __future__ import annotations

import numpy as np
import wgpu

from ..shaders import create_shader_module
from .base import Stage

# NDC positions (x right, y up in wgpu; see docs/vulkan-mapping.md for Vulkan's y-down)
# and linear RGB colours. shaders_wgsl/triangle.wgsl holds the same numbers.
TRIANGLE_POSITIONS = np.array([[-0.8, -0.7], [0.7, -0.5], [-0.1, 0.8]], dtype=np.float32)
TRIANGLE_COLORS = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
BACKGROUND = (0.0, 0.0, 0.0, 1.0)


def triangle_pipeline(stage: Stage, shader: str, vertex_buffers: list | None = None) -> wgpu.GPURenderPipeline:
    """The fixed-function state of the first triangle: no culling, no depth, one colour target."""
    module = create_shader_module(stage.device, shader)
    layout = stage.device.create_pipeline_layout(bind_group_layouts=[])
    return stage.device.create_render_pipeline(
        label=shader,
        layout=layout,
        vertex={"module": module, "entry_point": "vs_main", "buffers": vertex_buffers or []},
        primitive={"topology": "triangle-list", "front_face": "ccw", "cull_mode": "none"},
        depth_stencil=None,
        multisample=stage.multisample_state(),
        fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": stage.format}]},
    )


class Triangle(Stage):
    name = "triangle"
    summary = "first triangle, no vertex buffer: positions and colours from the vertex index"
    course_step = "2a: first triangle in NDC, attribute-less"
    order = 2.0
    supports_msaa = True

    def setup(self) -> None:
        self.pipeline = triangle_pipeline(self, "triangle.wgsl")

    def draw(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, BACKGROUND)])
        render_pass.set_pipeline(self.pipeline)
        render_pass.draw(3)
        render_pass.end()
