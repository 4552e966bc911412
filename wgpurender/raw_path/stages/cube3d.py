"""Course step 4: rotating cubes with a depth buffer, two UBOs in two descriptor sets, push constants.

The scene (cubes, camera, mesh, colours, light) is the course core's
(wgpurender/core/course/cubes.py), as on the wgpu path; everything Vulkan is spelled
out here, with its own std140 packers (ubo.py) and GLSL:
- set 0: the camera UBO (UNIFORM_BUFFER, vertex + fragment), in HOST_VISIBLE
  memory written through a mapping each frame (the course's updateUniformBuffer);
- set 1: the object UBO (UNIFORM_BUFFER_DYNAMIC, vertex): every cube's block in
  one buffer at ubo.dynamic_stride apart, picked per draw by a dynamic offset;
- per-draw tint and object index as push constants (vkCmdPushConstants);
- a D32 depth attachment (compare LESS, cleared to 1.0), back faces culled with
  front face COUNTER_CLOCKWISE (the viewport flip keeps wgpu's winding).
"""

from __future__ import annotations

import vulkan as vk

from wgpurender.core.course import cubes as course
from wgpurender.raw_path.device import descriptors, ubo
from wgpurender.raw_path.device.images import Image, create_image
from wgpurender.raw_path.device.memory import HOST_MEMORY, create_buffer, upload_buffer, write_host_buffer
from wgpurender.raw_path.device.pipeline import (
    PipelineDesc,
    create_pipeline,
    create_pipeline_layout,
    set_viewport_and_scissor,
)
from wgpurender.raw_path.stages.base import RefStage

STRIDE = course.VERTEX_FLOATS * 4  # position, normal, colour: three vec3


def vertex_input() -> tuple[list, list]:
    bindings = [vk.VkVertexInputBindingDescription(binding=0, stride=STRIDE, inputRate=vk.VK_VERTEX_INPUT_RATE_VERTEX)]
    attributes = [
        vk.VkVertexInputAttributeDescription(location=k, binding=0, format=vk.VK_FORMAT_R32G32B32_SFLOAT, offset=12 * k)
        for k in range(3)
    ]
    return bindings, attributes


class Cube3D(RefStage):
    name = "3d"
    summary = "rotating cubes: depth buffer, camera and object UBOs in two descriptor sets, push constants"
    camera = course.CameraSpec()  # the demo window's orbit camera replaces it per instance

    def setup(self) -> None:
        ctx, owned = self.ctx, self.owned
        vertices, indices = course.cube_mesh()
        self.index_count = len(indices)
        vertex_stage, attr_read = vk.VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, vk.VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT
        self.vertex_buffer = upload_buffer(ctx, owned, vertices, vk.VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                           vertex_stage, attr_read)
        self.index_buffer = upload_buffer(ctx, owned, indices, vk.VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                          vertex_stage, vk.VK_ACCESS_INDEX_READ_BIT)
        self.cubes = course.DEFAULT_CUBES
        self.object_stride = ubo.dynamic_stride(ubo.OBJECT_SIZE, ctx.limits.min_uniform_buffer_offset_alignment)
        uniform = vk.VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT
        self.camera_buffer = create_buffer(ctx, owned, ubo.CAMERA_SIZE, uniform, HOST_MEMORY)
        self.object_buffer = create_buffer(ctx, owned, self.object_stride * len(self.cubes), uniform, HOST_MEMORY)
        self._setup_descriptors()
        self.single_pass(course.BACKGROUND, depth=True)
        bindings, attributes = vertex_input()
        desc = PipelineDesc("cube3d.vert", "cube3d.frag", bindings, attributes, samples=self.msaa,
                            cull_mode=vk.VK_CULL_MODE_BACK_BIT, depth_test=True)
        self.pipeline = create_pipeline(ctx, owned, desc, self.layout, self.render_pass)
        usage = vk.VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | vk.VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT
        self.depth = create_image(ctx, owned, self.size, course.DEPTH_FORMAT, usage, self.msaa, lazy=True)

    def _setup_descriptors(self) -> None:
        ctx, owned = self.ctx, self.owned
        vertex, fragment = vk.VK_SHADER_STAGE_VERTEX_BIT, vk.VK_SHADER_STAGE_FRAGMENT_BIT
        camera_bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, vertex | fragment)]
        object_bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, vertex)]
        set_layouts = [descriptors.create_set_layout(ctx, owned, b) for b in (camera_bindings, object_bindings)]
        pool = descriptors.create_pool(ctx, owned, [camera_bindings, object_bindings])
        self.camera_set, self.object_set = descriptors.allocate_sets(ctx, pool, set_layouts)
        descriptors.update(ctx, [
            descriptors.write_buffer(self.camera_set, 0, self.camera_buffer.handle, 0, ubo.CAMERA_SIZE),
            # range = one block: with a dynamic offset the descriptor is a window sliding over the buffer
            descriptors.write_buffer(self.object_set, 0, self.object_buffer.handle, 0, ubo.OBJECT_SIZE,
                                     vk.VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC),
        ])
        push = vk.VkPushConstantRange(stageFlags=vertex, offset=0, size=ubo.DRAW_SIZE)
        self.layout = create_pipeline_layout(ctx, owned, set_layouts, [push])

    def update_uniforms(self, t: float) -> None:
        """Host writes before the submit: vkQueueSubmit makes them visible to the device."""
        camera = course.camera_values(self.camera, self.size[0] / self.size[1])
        packed = ubo.pack_camera(camera["proj"], camera["view"], camera["light_dir"], camera["ambient"])
        write_host_buffer(self.ctx, self.camera_buffer, packed)
        blocks = [ubo.pack_object(o["world"], o["normal"]) for o in course.object_values(self.cubes, t)]
        write_host_buffer(self.ctx, self.object_buffer, ubo.pack_many(blocks, self.object_stride))

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        self.update_uniforms(t)
        self.begin_pass(cmd, target, self.depth)
        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.pipeline)
        set_viewport_and_scissor(cmd, self.size)
        vk.vkCmdBindVertexBuffers(cmd, 0, 1, [self.vertex_buffer.handle], [0])
        vk.vkCmdBindIndexBuffer(cmd, self.index_buffer.handle, 0, vk.VK_INDEX_TYPE_UINT16)
        graphics = vk.VK_PIPELINE_BIND_POINT_GRAPHICS
        vk.vkCmdBindDescriptorSets(cmd, graphics, self.layout, 0, 1, [self.camera_set], 0, None)
        for k, draw in enumerate(course.draw_values(self.cubes)):
            vk.vkCmdBindDescriptorSets(cmd, graphics, self.layout, 1, 1, [self.object_set], 1, [k * self.object_stride])
            data = vk.ffi.from_buffer(ubo.pack_draw(draw["tint"], draw["object_index"]))
            vk.vkCmdPushConstants(cmd, self.layout, vk.VK_SHADER_STAGE_VERTEX_BIT, 0, ubo.DRAW_SIZE, data)
            vk.vkCmdDrawIndexed(cmd, self.index_count, 1, 0, 0, 0)
        vk.vkCmdEndRenderPass(cmd)
