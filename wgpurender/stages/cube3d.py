"""Course step 4: rotating cubes with a depth buffer and uniform buffers in bind groups.

The course's UBO chapter maps onto wgpu like this:

- VkDescriptorSetLayout -> GPUBindGroupLayout, VkDescriptorSet -> GPUBindGroup,
  vkCmdBindDescriptorSets -> ``set_bind_group``. Two layouts, two sets: group 0 is
  the camera (written every frame, the course's updateUniformBuffer), group 1 the
  object (world and normal matrix).
- Several objects share ONE object buffer: each cube's data sits at a multiple of
  ``min-uniform-buffer-offset-alignment`` and the draw picks it with a dynamic offset
  (VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC: one set, one offset per object,
  instead of one descriptor set per object).
- Per-draw data (a tint and the object index) are push constants: wgpu calls them
  immediates (``var<immediate>``, ``set_immediates``). Where the device lacks the
  feature, the same Draw struct comes from a dynamic-offset uniform buffer in
  group 2 and the image is the same.

Every uniform struct is declared once below with :mod:`wgpurender.uniforms`; the
WGSL declarations are generated from it into shaders_wgsl/cube3d.wgsl, and matrices
are computed in float64 (:mod:`wgpurender.transforms`) and packed column-major
through ``transforms.to_gpu``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import wgpu

from .. import transforms as tf
from ..errors import UserError
from ..gpu import GPUContext
from ..shader_variants import specialise
from ..shaders import create_shader_module, load_wgsl
from ..uniforms import F32, MAT3, MAT4, U32, VEC3F, VEC4F, Struct, wgsl_structs
from .base import Stage

CAMERA = Struct("Camera", [("proj", MAT4), ("view", MAT4), ("light_dir", VEC3F), ("ambient", F32)])
OBJECT = Struct("ObjectData", [("world", MAT4), ("normal", MAT3)])
DRAW = Struct("Draw", [("tint", VEC4F), ("object_index", U32)])

SHADER = "cube3d.wgsl"
DEPTH_FORMAT = "depth32float"
BACKGROUND = (0.02, 0.02, 0.03, 1.0)

# Lighting (world space): direction towards the light, and the ambient floor.
LIGHT_DIR = np.array([0.4, 0.9, 0.6]) / np.linalg.norm([0.4, 0.9, 0.6])
AMBIENT = 0.2

# One flat colour per face (linear RGB), by outward normal; every channel >= 0.2.
FACE_NORMALS = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
FACE_COLORS = np.array(
    [
        [0.90, 0.25, 0.20],  # +x red
        [0.20, 0.80, 0.85],  # -x cyan
        [0.30, 0.85, 0.25],  # +y green
        [0.85, 0.30, 0.80],  # -y magenta
        [0.25, 0.35, 0.90],  # +z blue
        [0.90, 0.85, 0.25],  # -z yellow
    ]
)


def permute_channels(rgb: np.ndarray, object_index: int) -> np.ndarray:
    """The shader's per-object channel order (rgb, gbr, brg), for references in numpy."""
    return np.asarray(rgb)[..., [(0, 1, 2), (1, 2, 0), (2, 0, 1)][object_index % 3]]


def cube_mesh() -> tuple[np.ndarray, np.ndarray]:
    """A cube of half-size 1: 24 vertices (position, normal, colour as float32) and 36 uint16 indices.

    Each face has its own 4 vertices so normal and colour are flat. Triangles wind
    counter-clockwise seen from outside (right-handed: u x v = n).
    """
    vertices, indices = [], []
    for n, color in zip(FACE_NORMALS, FACE_COLORS, strict=True):
        u = np.roll(n, 1)
        v = np.cross(n, u)
        base = len(vertices)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            vertices.append(np.concatenate([n + su * u + sv * v, n, color]))
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return np.array(vertices, dtype=np.float32), np.array(indices, dtype=np.uint16)


VERTEX_LAYOUT = {
    "array_stride": 9 * 4,
    "step_mode": "vertex",
    "attributes": [
        {"shader_location": 0, "format": "float32x3", "offset": 0},
        {"shader_location": 1, "format": "float32x3", "offset": 3 * 4},
        {"shader_location": 2, "format": "float32x3", "offset": 6 * 4},
    ],
}


@dataclass(frozen=True)
class CubeSpec:
    """One cube: where it is, how it spins (``speed`` degrees per second about ``axis``), its tint."""

    position: tuple[float, float, float]
    axis: tuple[float, float, float] = (0.0, 1.0, 0.0)
    speed: float = 90.0
    phase: float = 0.0  # degrees at t = 0
    half_size: float = 0.6
    tint: tuple[float, float, float, float] = (1.0, 1.0, 1.0, 1.0)

    def world(self, t: float) -> np.ndarray:
        """float64 model matrix at time ``t`` (seconds): translate * rotate * scale."""
        angle = np.radians(self.phase + self.speed * t)
        return tf.translate(self.position) @ tf.rotate(self.axis, angle) @ tf.scale(self.half_size)


@dataclass(frozen=True)
class CameraSpec:
    eye: tuple[float, float, float] = (0.0, 2.5, 7.0)
    target: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    fov_y: float = 45.0
    near: float = 0.1
    far: float = 50.0

    def matrices(self, aspect: float) -> tuple[np.ndarray, np.ndarray]:
        """(proj, view), float64."""
        return tf.perspective(self.fov_y, aspect, self.near, self.far), tf.look_at(self.eye, self.target, self.up)


DEFAULT_CUBES = (
    CubeSpec((-2.1, 0.0, 0.0), axis=(0, 1, 0), speed=90.0, phase=30.0, half_size=0.6),
    CubeSpec((0.0, 0.0, 0.0), axis=(1, 1, 0), speed=60.0, phase=20.0, half_size=0.7, tint=(1.0, 0.85, 0.7, 1.0)),
    CubeSpec((2.1, 0.0, 0.0), axis=(0, 0, 1), speed=45.0, phase=-25.0, half_size=0.6, tint=(0.75, 0.9, 1.0, 1.0)),
)


def _uniform_layout(device: wgpu.GPUDevice, struct: Struct, visibility: int, dynamic: bool) -> wgpu.GPUBindGroupLayout:
    return device.create_bind_group_layout(
        label=f"{struct.name}-layout",
        entries=[
            {
                "binding": 0,
                "visibility": visibility,
                "buffer": {"type": "uniform", "has_dynamic_offset": dynamic, "min_binding_size": struct.size},
            }
        ],
    )


class Cube3D(Stage):
    name = "3d"
    summary = "rotating cubes: depth buffer, camera and object UBOs in two bind groups, dynamic offsets, immediates"
    course_step = "4: 3D with uniform buffers in bind groups (descriptor sets) and push constants"
    order = 4.0
    supports_msaa = True

    def __init__(
        self,
        ctx: GPUContext,
        color_format: str,
        msaa: int | None = None,
        *,
        use_immediates: bool | None = None,
        cubes: Sequence[CubeSpec] = DEFAULT_CUBES,
        camera: CameraSpec | None = None,
    ) -> None:
        """``use_immediates``: None uses them when the device offers them, False forces the UBO fallback."""
        if use_immediates and not ctx.has("immediates"):
            raise UserError(
                f"{ctx.adapter.info['device']} does not offer the 'immediates' feature (push constants): "
                "leave use_immediates unset to fall back to a uniform buffer"
            )
        self.uses_immediates = ctx.has("immediates") if use_immediates is None else bool(use_immediates)
        if not cubes:
            raise UserError("stage 3d needs at least one cube")
        self.cubes = tuple(cubes)
        self.camera = camera or CameraSpec()
        self._depth_view: wgpu.GPUTextureView | None = None
        super().__init__(ctx, color_format, msaa)

    # -- set-up ----------------------------------------------------------------
    def setup(self) -> None:
        dev = self.device
        vertices, indices = cube_mesh()
        self.index_count = len(indices)
        self.vertex_buffer = dev.create_buffer_with_data(data=vertices, usage=wgpu.BufferUsage.VERTEX)
        self.index_buffer = dev.create_buffer_with_data(data=indices, usage=wgpu.BufferUsage.INDEX)

        # Dynamic offsets must be multiples of this device limit (256 on most GPUs).
        self.offset_alignment = self.ctx.limit("min-uniform-buffer-offset-alignment")
        self.object_stride = OBJECT.stride(self.offset_alignment)
        self.draw_stride = DRAW.stride(self.offset_alignment)
        n = len(self.cubes)
        usage = wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST
        self.camera_buffer = dev.create_buffer(label="camera-ubo", size=CAMERA.size, usage=usage)
        self.object_buffer = dev.create_buffer(label="object-ubo", size=self.object_stride * n, usage=usage)

        stages = wgpu.ShaderStage.VERTEX | wgpu.ShaderStage.FRAGMENT
        layouts = [
            _uniform_layout(dev, CAMERA, stages, dynamic=False),
            _uniform_layout(dev, OBJECT, wgpu.ShaderStage.VERTEX, dynamic=True),
        ]
        self.camera_group = self._bind_group(layouts[0], self.camera_buffer, CAMERA)
        self.object_group = self._bind_group(layouts[1], self.object_buffer, OBJECT)
        self.draw_group = None
        if not self.uses_immediates:
            layouts.append(_uniform_layout(dev, DRAW, wgpu.ShaderStage.VERTEX, dynamic=True))
            self.draw_buffer = dev.create_buffer(label="draw-ubo", size=self.draw_stride * n, usage=usage)
            self.draw_group = self._bind_group(layouts[2], self.draw_buffer, DRAW)
        immediate_size = DRAW.size if self.uses_immediates else 0
        pipeline_layout = dev.create_pipeline_layout(bind_group_layouts=layouts, immediate_size=immediate_size)
        self.pipeline = self._pipeline(pipeline_layout)

    def _bind_group(self, layout, buffer: wgpu.GPUBuffer, struct: Struct) -> wgpu.GPUBindGroup:
        # size = one struct, not the whole buffer: with a dynamic offset the binding is a window into it.
        return self.device.create_bind_group(
            layout=layout, entries=[{"binding": 0, "resource": {"buffer": buffer, "offset": 0, "size": struct.size}}]
        )

    def shader_source(self) -> str:
        """cube3d.wgsl with the generated structs and the immediates or uniform-buffer Draw variant.

        Two variants from one file (#if immediates), not an override constant: a module that
        declares var<immediate> does not compile where the feature is missing, whatever an
        override says, and the UBO variant needs a third bind group the other must not have.
        """
        features = {"immediates"} if self.uses_immediates else set()
        structs = wgsl_structs(CAMERA, OBJECT, DRAW)
        return specialise(load_wgsl(SHADER), features, {"STRUCTS": structs}, name=SHADER)

    def _pipeline(self, layout: wgpu.GPUPipelineLayout) -> wgpu.GPURenderPipeline:
        module = create_shader_module(self.device, SHADER, self.shader_source())
        return self.device.create_render_pipeline(
            label="cube3d",
            layout=layout,
            vertex={"module": module, "entry_point": "vs_main", "buffers": [VERTEX_LAYOUT]},
            primitive={"topology": "triangle-list", "front_face": "ccw", "cull_mode": "back"},
            depth_stencil={"format": DEPTH_FORMAT, "depth_write_enabled": True, "depth_compare": "less"},
            multisample=self.multisample_state(),
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": self.format}]},
        )

    def on_resize(self, size: tuple[int, int]) -> None:
        depth = self.device.create_texture(
            label="cube3d-depth",
            size=(size[0], size[1], 1),
            format=DEPTH_FORMAT,
            usage=wgpu.TextureUsage.RENDER_ATTACHMENT,
            sample_count=self.msaa,
        )
        self._depth_view = depth.create_view()

    # -- per frame -------------------------------------------------------------
    def camera_values(self) -> dict:
        proj, view = self.camera.matrices(self.size[0] / self.size[1])
        return {"proj": proj, "view": view, "light_dir": LIGHT_DIR, "ambient": AMBIENT}

    def object_values(self, t: float) -> list[dict]:
        worlds = [cube.world(t) for cube in self.cubes]
        return [{"world": w, "normal": tf.normal_matrix(w)} for w in worlds]

    def draw_values(self) -> list[dict]:
        return [{"tint": cube.tint, "object_index": k} for k, cube in enumerate(self.cubes)]

    def draw(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        if self._depth_view is None or tuple(target.size[:2]) != self.size:
            self.resize(tuple(target.size[:2]))
        queue = self.ctx.queue
        queue.write_buffer(self.camera_buffer, 0, CAMERA.pack(self.camera_values()))
        queue.write_buffer(self.object_buffer, 0, OBJECT.pack_many(self.object_values(t), self.offset_alignment))
        draws = [DRAW.pack(values) for values in self.draw_values()]
        if not self.uses_immediates:
            queue.write_buffer(self.draw_buffer, 0, DRAW.pack_many(self.draw_values(), self.offset_alignment))

        render_pass = encoder.begin_render_pass(
            color_attachments=[self.color_attachment(target, BACKGROUND)],
            depth_stencil_attachment={
                "view": self._depth_view,
                "depth_clear_value": 1.0,
                "depth_load_op": "clear",
                "depth_store_op": "discard",
            },
        )
        render_pass.set_pipeline(self.pipeline)
        render_pass.set_vertex_buffer(0, self.vertex_buffer)
        render_pass.set_index_buffer(self.index_buffer, "uint16")
        render_pass.set_bind_group(0, self.camera_group)
        for k, data in enumerate(draws):
            render_pass.set_bind_group(1, self.object_group, [k * self.object_stride])
            if self.uses_immediates:
                render_pass.set_immediates(0, data, 0, DRAW.size)
            else:
                render_pass.set_bind_group(2, self.draw_group, [k * self.draw_stride])
            render_pass.draw_indexed(self.index_count)
        render_pass.end()
