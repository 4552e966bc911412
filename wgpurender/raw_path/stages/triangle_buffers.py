"""Course step 2b: the triangle from a vertex buffer and an index buffer, with an explicit input layout.

Both buffers are DEVICE_LOCAL and filled by staging uploads (memory.upload_buffer).
The input layout: one VkVertexInputBindingDescription (binding 0, stride 20
bytes, per vertex) and two VkVertexInputAttributeDescriptions (location 0:
R32G32_SFLOAT position at offset 0; location 1: R32G32B32_SFLOAT colour at 8).
"""

from __future__ import annotations

import vulkan as vk

from wgpurender.core.course.triangle import BACKGROUND, TRIANGLE_INDICES, triangle_vertices
from wgpurender.raw_path.device.images import Image
from wgpurender.raw_path.device.memory import upload_buffer
from wgpurender.raw_path.device.pipeline import set_viewport_and_scissor
from wgpurender.raw_path.stages.base import RefStage

STRIDE = 5 * 4


def vertex_input() -> tuple[list, list]:
    bindings = [vk.VkVertexInputBindingDescription(binding=0, stride=STRIDE, inputRate=vk.VK_VERTEX_INPUT_RATE_VERTEX)]
    attributes = [
        vk.VkVertexInputAttributeDescription(location=0, binding=0, format=vk.VK_FORMAT_R32G32_SFLOAT, offset=0),
        vk.VkVertexInputAttributeDescription(location=1, binding=0, format=vk.VK_FORMAT_R32G32B32_SFLOAT, offset=8),
    ]
    return bindings, attributes


class TriangleBuffers(RefStage):
    name = "triangle-buffers"
    summary = "first triangle from a vertex buffer and an index buffer with an explicit input layout"

    def setup(self) -> None:
        stage, access = vk.VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, vk.VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT
        self.vertex_buffer = upload_buffer(self.ctx, self.owned, triangle_vertices(),
                                           vk.VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, stage, access)
        self.index_buffer = upload_buffer(self.ctx, self.owned, TRIANGLE_INDICES, vk.VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                          stage, vk.VK_ACCESS_INDEX_READ_BIT)
        self.single_pass(BACKGROUND)
        self.pipeline = self.basic_pipeline("triangle_buffers.vert", "color.frag", *vertex_input())

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        self.begin_pass(cmd, target)
        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.pipeline)
        set_viewport_and_scissor(cmd, self.size)
        vk.vkCmdBindVertexBuffers(cmd, 0, 1, [self.vertex_buffer.handle], [0])
        vk.vkCmdBindIndexBuffer(cmd, self.index_buffer.handle, 0, vk.VK_INDEX_TYPE_UINT16)
        vk.vkCmdDrawIndexed(cmd, len(TRIANGLE_INDICES), 1, 0, 0, 0)
        vk.vkCmdEndRenderPass(cmd)
