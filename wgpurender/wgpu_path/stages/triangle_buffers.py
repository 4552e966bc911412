"""Course step 2b: the first triangle from a vertex buffer and an index buffer.

The vertex layout below is the course's input layout: one binding (stride 20
bytes, per-vertex), two attributes (location 0: float32x2 position at offset 0;
location 1: float32x3 colour at offset 8).
"""

from __future__ import annotations

import numpy as np
import wgpu

from wgpurender.core.course.triangle import BACKGROUND, TRIANGLE_INDICES, triangle_vertices
from wgpurender.wgpu_path.stages.base import Stage

VERTEX_LAYOUT = {
    "array_stride": 5 * 4,
    "step_mode": "vertex",
    "attributes": [
        {"shader_location": 0, "format": "float32x2", "offset": 0},
        {"shader_location": 1, "format": "float32x3", "offset": 2 * 4},
    ],
}
INDICES = np.concatenate([TRIANGLE_INDICES, [0]]).astype(np.uint16)  # one pad index: writes are 4-byte multiples


class TriangleBuffers(Stage):
    name = "triangle-buffers"
    summary = "first triangle from a vertex buffer and an index buffer with an explicit vertex layout"

    def setup(self) -> None:
        # create_buffer_with_data stands for the course's staging upload: wgpu copies
        # the bytes into device memory for us (a mapped-at-creation buffer).
        vertices = triangle_vertices()
        self.vertex_buffer = self.device.create_buffer_with_data(data=vertices, usage=wgpu.BufferUsage.VERTEX)
        self.index_buffer = self.device.create_buffer_with_data(data=INDICES, usage=wgpu.BufferUsage.INDEX)
        self.pipeline = self.basic_pipeline("triangle_buffers.wgsl", [VERTEX_LAYOUT])

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, BACKGROUND)])
        render_pass.set_pipeline(self.pipeline)
        render_pass.set_vertex_buffer(0, self.vertex_buffer)
        render_pass.set_index_buffer(self.index_buffer, "uint16")
        render_pass.draw_indexed(len(TRIANGLE_INDICES))
        render_pass.end()
