"""Course step 5: a textured plane at a grazing angle, combined vs separate image samplers.

The scene is the course core's (course/textured.py: pattern, plane, lanes, camera, samplers), as
on the wgpu path; everything Vulkan is spelled out here and in raw_path/device/textures.py:
- the texture: a staging upload into an R8G8B8A8_SRGB image with a full mip chain, each level drawn
  from the previous one by a render pass (the wgpu path's filter; see textures.py for why not vkCmdBlitImage);
- left half: set 1 holds ONE descriptor of type COMBINED_IMAGE_SAMPLER (image view + sampler,
  GLSL sampler2D), the course's combined variant, which wgpu cannot express;
- right half: set 1 holds a SAMPLED_IMAGE (GLSL texture2D), bound once, and set 2 a SAMPLER,
  re-bound for each of the four lanes (nearest no mips, bilinear no mips, trilinear,
  trilinear + 16x anisotropy);
- set 0: the uniform block (mvp, uv_offset), one buffer and set per half, hand-packed std140;
- the two halves are two viewports (flipped like every viewport of this path) over one render
  pass; the scissor stays the whole image, as in wgpu, whose set_viewport leaves it alone.
"""

from __future__ import annotations

import numpy as np
import vulkan as vk

from wgpurender.core.course import textured as course
from wgpurender.core.view.transforms import to_gpu
from wgpurender.raw_path.device import descriptors
from wgpurender.raw_path.device.images import Image
from wgpurender.raw_path.device.memory import HOST_MEMORY, create_buffer, upload_buffer, write_host_buffer
from wgpurender.raw_path.device.pipeline import (
    PipelineDesc,
    create_pipeline,
    create_pipeline_layout,
    set_viewport_and_scissor,
)
from wgpurender.raw_path.device.textures import create_sampler, upload_texture
from wgpurender.raw_path.stages.base import RefStage

STRIDE = course.VERTEX_FLOATS * 4  # vec3 position, vec2 uv
# layout(std140) uniform Uniforms { mat4 mvp; vec4 uv_offset; }
UNIFORM_SIZE = 64 + 16  # mvp @0, uv_offset @64
READ_ONLY = vk.VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL
FRAGMENT = vk.VK_SHADER_STAGE_FRAGMENT_BIT


def vertex_input() -> tuple[list, list]:
    bindings = [vk.VkVertexInputBindingDescription(binding=0, stride=STRIDE, inputRate=vk.VK_VERTEX_INPUT_RATE_VERTEX)]
    attributes = [
        vk.VkVertexInputAttributeDescription(location=0, binding=0, format=vk.VK_FORMAT_R32G32B32_SFLOAT, offset=0),
        vk.VkVertexInputAttributeDescription(location=1, binding=0, format=vk.VK_FORMAT_R32G32_SFLOAT, offset=12),
    ]
    return bindings, attributes


def pack_uniforms(mvp: np.ndarray, uv_offset) -> bytes:
    """The std140 block: mvp column-major at 0, uv_offset (xy used, zw zero) at 64."""
    buf = np.zeros(UNIFORM_SIZE // 4, dtype=np.float32)
    buf[0:16] = to_gpu(mvp).reshape(-1)
    buf[16:18] = uv_offset
    return buf.tobytes()


def set_viewport(cmd, x: int, width: int, height: int) -> None:
    """A viewport over columns x..x+width, flipped (y = height, height < 0) like set_viewport_and_scissor."""
    viewport = vk.VkViewport(x=float(x), y=float(height), width=float(width), height=-float(height),
                             minDepth=0.0, maxDepth=1.0)
    vk.vkCmdSetViewport(cmd, 0, 1, [viewport])


class Textured(RefStage):
    name = "textured"
    summary = "a generated sRGB texture with a mip chain: a combined image sampler vs one image and 4 samplers"

    def setup(self) -> None:
        ctx, owned = self.ctx, self.owned
        self.texture = upload_texture(ctx, owned, course.pattern_pixels(), srgb=True, mips=True)
        vertices = course.stage_vertices()  # 0..5 the whole plane, then 6 per lane
        self.vertex_buffer = upload_buffer(ctx, owned, vertices, vk.VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                           vk.VK_PIPELINE_STAGE_VERTEX_INPUT_BIT,
                                           vk.VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT)
        uniform = vk.VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT
        self.uniform_buffers = [create_buffer(ctx, owned, UNIFORM_SIZE, uniform, HOST_MEMORY) for _ in range(2)]
        self.combined_sampler = create_sampler(ctx, owned, course.COMBINED_SAMPLER)
        self.lane_samplers = [create_sampler(ctx, owned, spec) for _, spec in course.SEPARATE_SAMPLERS]
        self._setup_descriptors()
        self.single_pass(course.BACKGROUND)
        bindings, attributes = vertex_input()

        def desc(frag: str) -> PipelineDesc:
            return PipelineDesc("textured.vert", frag, bindings, attributes, samples=self.msaa)

        self.combined_pipeline, self.separate_pipeline = (
            create_pipeline(ctx, owned, desc(f"textured_{kind}.frag"), layout, self.render_pass)
            for kind, layout in (("combined", self.combined_layout), ("separate", self.separate_layout)))

    def _setup_descriptors(self) -> None:
        ctx, owned = self.ctx, self.owned
        uniform_bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, vk.VK_SHADER_STAGE_VERTEX_BIT)]
        combined_bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, FRAGMENT)]
        image_bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, FRAGMENT)]
        sampler_bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_SAMPLER, FRAGMENT)]
        uniform_layout, combined_layout, image_layout, sampler_layout = (
            descriptors.create_set_layout(ctx, owned, b)
            for b in (uniform_bindings, combined_bindings, image_bindings, sampler_bindings)
        )
        lanes = len(self.lane_samplers)
        per_set = [uniform_bindings] * 2 + [combined_bindings, image_bindings] + [sampler_bindings] * lanes
        pool = descriptors.create_pool(ctx, owned, per_set)
        layouts = [uniform_layout] * 2 + [combined_layout, image_layout] + [sampler_layout] * lanes
        sets = descriptors.allocate_sets(ctx, pool, layouts)
        self.uniform_sets, (self.combined_set, self.image_set), self.sampler_sets = sets[:2], sets[2:4], sets[4:]
        view = self.texture.view
        descriptors.update(ctx, [
            *(descriptors.write_buffer(s, 0, b.handle, 0, UNIFORM_SIZE)
              for s, b in zip(self.uniform_sets, self.uniform_buffers, strict=True)),
            descriptors.write_image(self.combined_set, 0, view, READ_ONLY, vk.VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                    self.combined_sampler),
            descriptors.write_image(self.image_set, 0, view, READ_ONLY, vk.VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE),
            *(descriptors.write_image(s, 0, None, READ_ONLY, vk.VK_DESCRIPTOR_TYPE_SAMPLER, sampler)
              for s, sampler in zip(self.sampler_sets, self.lane_samplers, strict=True)),
        ])
        self.combined_layout = create_pipeline_layout(ctx, owned, [uniform_layout, combined_layout])
        self.separate_layout = create_pipeline_layout(ctx, owned, [uniform_layout, image_layout, sampler_layout])

    def update_uniforms(self, t: float) -> None:
        height = self.size[1]
        for buffer, (_, w) in zip(self.uniform_buffers, course.halves(self.size[0]), strict=True):
            mvp = course.plane_mvp(max(w, 1) / max(height, 1))
            write_host_buffer(self.ctx, buffer, pack_uniforms(mvp, course.uv_offset(t)))

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        self.update_uniforms(t)
        self.begin_pass(cmd, target)
        graphics, height = vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.size[1]
        (lx, lw), (rx, rw) = course.halves(self.size[0])
        vk.vkCmdBindVertexBuffers(cmd, 0, 1, [self.vertex_buffer.handle], [0])
        if lw > 0:
            vk.vkCmdBindPipeline(cmd, graphics, self.combined_pipeline)
            set_viewport_and_scissor(cmd, self.size)  # the scissor: the whole image
            set_viewport(cmd, lx, lw, height)
            sets = [self.uniform_sets[0], self.combined_set]
            vk.vkCmdBindDescriptorSets(cmd, graphics, self.combined_layout, 0, 2, sets, 0, None)
            vk.vkCmdDraw(cmd, 6, 1, 0, 0)
        if rw > 0:
            vk.vkCmdBindPipeline(cmd, graphics, self.separate_pipeline)
            set_viewport_and_scissor(cmd, self.size)
            set_viewport(cmd, rx, rw, height)
            sets = [self.uniform_sets[1], self.image_set]  # the image set stays bound for all four samplers
            vk.vkCmdBindDescriptorSets(cmd, graphics, self.separate_layout, 0, 2, sets, 0, None)
            for lane, sampler_set in enumerate(self.sampler_sets):
                vk.vkCmdBindDescriptorSets(cmd, graphics, self.separate_layout, 2, 1, [sampler_set], 0, None)
                vk.vkCmdDraw(cmd, 6, 1, 6 * (lane + 1), 0)
        vk.vkCmdEndRenderPass(cmd)
