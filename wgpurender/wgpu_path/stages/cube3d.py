"""Course step 4: rotating cubes with a depth buffer and uniform buffers in bind groups.

The course's UBO chapter maps onto wgpu like this:

- VkDescriptorSetLayout -> GPUBindGroupLayout, VkDescriptorSet -> GPUBindGroup, vkCmdBindDescriptorSets ->
  ``set_bind_group``. Two layouts, two sets: group 0 is the camera (written when its values change, the course's
  updateUniformBuffer), group 1 the object (world and normal matrix).
- Several objects share ONE object buffer: each cube's data sits at a multiple of ``min-uniform-
  buffer-offset-alignment``, picked per draw by a dynamic offset (UNIFORM_BUFFER_DYNAMIC).
- Per-draw data (a tint and the object index) are push constants: wgpu calls them
  immediates (``var<immediate>``, ``set_immediates``). Where the device lacks the
  feature, the same Draw struct comes from a dynamic-offset uniform buffer in
  group 2 and the image is the same.

The scene is the course core's (course/cubes.py). Uniform structs are declared once below
(:mod:`wgpurender.core.shaders.uniforms`), which generates their WGSL into shaders_wgsl/cube3d.wgsl.
"""

from __future__ import annotations

from collections.abc import Sequence

import wgpu

from wgpurender.core.course import cubes as course
from wgpurender.core.errors import UserError
from wgpurender.core.shaders.shader_variants import specialise
from wgpurender.core.shaders.uniforms import F32, MAT3, MAT4, U32, VEC3F, VEC4F, Struct, wgsl_structs
from wgpurender.wgpu_path.device.bind_groups import uniform_group, uniform_layout
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module, load_wgsl
from wgpurender.wgpu_path.stages.base import Stage

CAMERA = Struct("Camera", [("proj", MAT4), ("view", MAT4), ("light_dir", VEC3F), ("ambient", F32)])
OBJECT = Struct("ObjectData", [("world", MAT4), ("normal", MAT3)])
DRAW = Struct("Draw", [("tint", VEC4F), ("object_index", U32)])
SHADER = "cube3d.wgsl"
VERTEX_LAYOUT = {
    "array_stride": course.VERTEX_FLOATS * 4,
    "step_mode": "vertex",
    "attributes": [{"shader_location": k, "format": "float32x3", "offset": 12 * k} for k in range(3)],
}


class Cube3D(Stage):
    name = "3d"
    summary = "rotating cubes: depth buffer, camera and object UBOs in two bind groups, dynamic offsets, immediates"

    def __init__(self, ctx: GPUContext, color_format: str, msaa: int | None = None, *,
                 use_immediates: bool | None = None, cubes: Sequence[course.CubeSpec] = course.DEFAULT_CUBES,
                 camera: course.CameraSpec | None = None) -> None:
        """``use_immediates``: None uses them when the device offers them, False forces the UBO fallback."""
        self.uses_immediates = ctx.use_immediates(use_immediates)
        if not cubes:
            raise UserError("stage 3d needs at least one cube")
        self.cubes, self.camera = tuple(cubes), camera or course.CameraSpec()
        self._depth_view: wgpu.GPUTextureView | None = None
        self._camera_bytes: bytes | None = None  # the camera block last written (rewritten when its values change)
        self._draws = [DRAW.pack(values) for values in course.draw_values(self.cubes)]  # tints, indices: fixed
        super().__init__(ctx, color_format, msaa)

    def setup(self) -> None:
        dev, n = self.device, len(self.cubes)
        vertices, indices = course.cube_mesh()
        self.index_count = len(indices)
        self.vertex_buffer = dev.create_buffer_with_data(data=vertices, usage=wgpu.BufferUsage.VERTEX)
        self.index_buffer = dev.create_buffer_with_data(data=indices, usage=wgpu.BufferUsage.INDEX)
        # Dynamic offsets must be multiples of this device limit (256 on most GPUs).
        self.offset_alignment = self.ctx.limit("min-uniform-buffer-offset-alignment")
        self.object_stride = OBJECT.stride(self.offset_alignment)
        self.draw_stride = DRAW.stride(self.offset_alignment)
        usage = wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST
        self.camera_buffer = dev.create_buffer(label="camera-ubo", size=CAMERA.size, usage=usage)
        self.object_buffer = dev.create_buffer(label="object-ubo", size=self.object_stride * n, usage=usage)
        vertex = wgpu.ShaderStage.VERTEX
        layouts = [uniform_layout(dev, CAMERA, vertex | wgpu.ShaderStage.FRAGMENT, dynamic=False),
                   uniform_layout(dev, OBJECT, vertex, dynamic=True)]
        self.camera_group = uniform_group(dev, layouts[0], self.camera_buffer, CAMERA)
        self.object_group = uniform_group(dev, layouts[1], self.object_buffer, OBJECT)
        self.draw_group = None
        if not self.uses_immediates:
            layouts.append(uniform_layout(dev, DRAW, vertex, dynamic=True))
            self.draw_buffer = dev.create_buffer(label="draw-ubo", size=self.draw_stride * n, usage=usage)
            self.draw_group = uniform_group(dev, layouts[2], self.draw_buffer, DRAW)
        immediate_size = DRAW.size if self.uses_immediates else 0
        self.pipeline = self._pipeline(dev.create_pipeline_layout(bind_group_layouts=layouts,
                                                                  immediate_size=immediate_size))

    def shader_source(self) -> str:
        """cube3d.wgsl with the generated structs and the immediates or uniform-buffer Draw variant.

        Two variants from one file (#if immediates), not an override constant: a module that
        declares var<immediate> does not compile where the feature is missing, whatever an
        override says, and the UBO variant needs a third bind group the other must not have.
        """
        features = {"immediates"} if self.uses_immediates else set()
        return specialise(load_wgsl(SHADER), features, {"STRUCTS": wgsl_structs(CAMERA, OBJECT, DRAW)}, name=SHADER)

    def _pipeline(self, layout: wgpu.GPUPipelineLayout) -> wgpu.GPURenderPipeline:
        module = create_shader_module(self.device, SHADER, self.shader_source())
        return self.device.create_render_pipeline(
            label="cube3d",
            layout=layout,
            vertex={"module": module, "entry_point": "vs_main", "buffers": [VERTEX_LAYOUT]},
            primitive={"topology": "triangle-list", "front_face": "ccw", "cull_mode": "back"},
            depth_stencil={"format": course.DEPTH_FORMAT, "depth_write_enabled": True, "depth_compare": "less"},
            multisample=self.multisample_state(),
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": self.format}]},
        )

    def on_resize(self, size: tuple[int, int]) -> None:
        self._depth_view = self.device.create_texture(
            label="cube3d-depth", size=(size[0], size[1], 1), format=course.DEPTH_FORMAT,
            usage=wgpu.TextureUsage.RENDER_ATTACHMENT, sample_count=self.msaa,
        ).create_view()

    def update_uniforms(self, t: float) -> None:
        """The course's updateUniformBuffer: camera, every cube's matrices and (without immediates) draws."""
        queue = self.ctx.queue
        aspect = self.size[0] / self.size[1]
        camera = CAMERA.pack(course.camera_values(self.camera, aspect))
        if camera != self._camera_bytes:  # by value: a new camera (the window's orbit) or a new aspect
            queue.write_buffer(self.camera_buffer, 0, camera)
            self._camera_bytes = camera
        queue.write_buffer(self.object_buffer, 0, OBJECT.pack_many(course.object_values(self.cubes, t),
                                                                   self.offset_alignment))
        if not self.uses_immediates:
            draws = DRAW.pack_many(course.draw_values(self.cubes), self.offset_alignment)
            queue.write_buffer(self.draw_buffer, 0, draws)

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        if self._depth_view is None or tuple(target.size[:2]) != self.size:
            self.resize(tuple(target.size[:2]))
        self.update_uniforms(t)
        depth = {"view": self._depth_view, "depth_clear_value": 1.0, "depth_load_op": "clear",
                 "depth_store_op": "discard"}
        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, course.BACKGROUND)],
                                                depth_stencil_attachment=depth)
        render_pass.set_pipeline(self.pipeline)
        render_pass.set_vertex_buffer(0, self.vertex_buffer)
        render_pass.set_index_buffer(self.index_buffer, "uint16")
        render_pass.set_bind_group(0, self.camera_group)
        for k, data in enumerate(self._draws):
            render_pass.set_bind_group(1, self.object_group, [k * self.object_stride])
            if self.uses_immediates:
                render_pass.set_immediates(0, data, 0, DRAW.size)
            else:
                render_pass.set_bind_group(2, self.draw_group, [k * self.draw_stride])
            render_pass.draw_indexed(self.index_count)
        render_pass.end()
