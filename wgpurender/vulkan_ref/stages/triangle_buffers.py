"""Course step 2b: the triangle from a vertex buffer and an index buffer, with an explicit input layout.

Both buffers are DEVICE_LOCAL and filled by staging uploads (memory.upload_buffer).
The input layout: one VkVertexInputBindingDescription (binding 0, stride 20
bytes, per vertex) and two VkVertexInputAttributeDescriptions (location 0:
R32G32_SFLOAT position at offset 0; location 1: R32G32B32_SFLOAT colour at 8).
"""

from __future__ import annotations

import numpy as np
import vulkan as vk

from ..memory import upload_buffer
from ..pipeline import PipelineDesc
from .triangle import TRIANGLE_COLORS, TRIANGLE_POSITIONS, Triangle

INDICES = np.array([0, 1, 2], dtype=np.uint16)
STRIDE = 5 * 4


def vertex_input() -> tuple[list, list]:
    bindings = [vk.VkVertexInputBindingDescription(binding=0, stride=STRIDE, inputRate=vk.VK_VERTEX_INPUT_RATE_VERTEX)]
    attributes = [
        vk.VkVertexInputAttributeDescription(location=0, binding=0, format=vk.VK_FORMAT_R32G32_SFLOAT, offset=0),
        vk.VkVertexInputAttributeDescription(location=1, binding=0, format=vk.VK_FORMAT_R32G32B32_SFLOAT, offset=8),
    ]
    return bindings, attributes


class TriangleBuffers(Triangle):
    name = "triangle-buffers"
    summary = "first triangle from a vertex buffer and an index buffer with an explicit input layout"
    order = 2.1
    vertex_shader = "triangle_buffers.vert"

    def setup(self) -> None:
        vertices = np.hstack([TRIANGLE_POSITIONS, TRIANGLE_COLORS]).astype(np.float32)
        stage, access = vk.VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, vk.VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT
        self.vertex_buffer = upload_buffer(self.ctx, self.owned, vertices, vk.VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                           stage, access)
        self.index_buffer = upload_buffer(self.ctx, self.owned, INDICES, vk.VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                          stage, vk.VK_ACCESS_INDEX_READ_BIT)
        super().setup()

    def pipeline_desc(self) -> PipelineDesc:
        bindings, attributes = vertex_input()
        return PipelineDesc(vert=self.vertex_shader, frag="color.frag", samples=self.msaa,
                            vertex_bindings=bindings, vertex_attributes=attributes)

    def draw(self, cmd) -> None:
        vk.vkCmdBindVertexBuffers(cmd, 0, 1, [self.vertex_buffer.handle], [0])
        vk.vkCmdBindIndexBuffer(cmd, self.index_buffer.handle, 0, vk.VK_INDEX_TYPE_UINT16)
        vk.vkCmdDrawIndexed(cmd, len(INDICES), 1, 0, 0, 0)
