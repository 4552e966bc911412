"""Course step 5: textures and samplers, combined and separate, on a plane seen at a grazing angle.

Left half: the plane drawn with its texture and its own sampler in ONE bind group
(the combined image sampler of the course). Right half: the same plane cut into
four lanes along its length, ONE texture bound once and four samplers swapped
between the lanes' draws (separate sampled image + samplers), from left to right:
nearest without mips, bilinear without mips, trilinear, trilinear with 16x
anisotropy. Far away the first two alias (moire), trilinear blurs, anisotropic
stays sharp.

The texture, plane and samplers are the course core's (course/textured.py). The texture is
uploaded as rgba8unorm-srgb and gets a gamma-correct mip chain on the GPU (textures.py).
"""

from __future__ import annotations

import numpy as np
import wgpu

from wgpurender.core.course import textured as course
from wgpurender.core.view.transforms import to_gpu
from wgpurender.wgpu_path.device.gpu_cache import device_cache
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.device.textures import create_sampler, create_texture
from wgpurender.wgpu_path.stages.base import Stage

VERTEX_LAYOUT = {
    "array_stride": course.VERTEX_FLOATS * 4,
    "step_mode": "vertex",
    "attributes": [
        {"shader_location": 0, "format": "float32x3", "offset": 0},
        {"shader_location": 1, "format": "float32x2", "offset": 3 * 4},
    ],
}
UNIFORM_SIZE = 64 + 16  # mat4x4f mvp, vec4f uv_offset


def uniform_bytes(mvp: np.ndarray, uv_offset=(0.0, 0.0)) -> bytes:
    data = np.zeros(UNIFORM_SIZE // 4, dtype=np.float32)
    data[:16] = to_gpu(mvp).reshape(-1)  # column-major: to_gpu does the one transpose
    data[16:18] = uv_offset
    return data.tobytes()


class TexturedPipelines:
    """The two pipelines (combined and separate bindings) for one colour format and sample count."""

    def __init__(self, device: wgpu.GPUDevice, fmt: str, sample_count: int = 1) -> None:
        self.device = device
        frag = wgpu.ShaderStage.FRAGMENT
        texture_entry = {"binding": 0, "visibility": frag, "texture": {"sample_type": "float", "view_dimension": "2d"}}
        self.uniform_layout = device.create_bind_group_layout(
            label="textured-uniforms",
            entries=[{"binding": 0, "visibility": wgpu.ShaderStage.VERTEX, "buffer": {"type": "uniform"}}],
        )
        # Combined: the descriptor set layout {0: sampled image, 1: sampler}.
        self.combined_layout = device.create_bind_group_layout(
            label="texture+sampler",
            entries=[texture_entry, {"binding": 1, "visibility": frag, "sampler": {"type": "filtering"}}],
        )
        # Separate: {0: sampled image} and, in its own set, {0: sampler}.
        self.texture_layout = device.create_bind_group_layout(label="texture", entries=[texture_entry])
        self.sampler_layout = device.create_bind_group_layout(
            label="sampler", entries=[{"binding": 0, "visibility": frag, "sampler": {"type": "filtering"}}]
        )
        module = create_shader_module(device, "textured.wgsl")
        combined_layouts = [self.uniform_layout, self.combined_layout]
        separate_layouts = [self.uniform_layout, self.texture_layout, self.sampler_layout]
        self.combined = self._pipeline(module, "fs_combined", combined_layouts, fmt, sample_count)
        self.separate = self._pipeline(module, "fs_separate", separate_layouts, fmt, sample_count)

    def _pipeline(self, module, entry: str, layouts: list, fmt: str, sample_count: int) -> wgpu.GPURenderPipeline:
        return self.device.create_render_pipeline(
            label=f"textured-{entry}",
            layout=self.device.create_pipeline_layout(bind_group_layouts=layouts),
            vertex={"module": module, "entry_point": "vs_main", "buffers": [VERTEX_LAYOUT]},
            primitive={"topology": "triangle-list", "front_face": "ccw", "cull_mode": "none"},
            depth_stencil=None,
            multisample={"count": sample_count, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
            fragment={"module": module, "entry_point": entry, "targets": [{"format": fmt}]},
        )

    def group(self, layout: wgpu.GPUBindGroupLayout, *resources) -> wgpu.GPUBindGroup:
        """A bind group with ``resources`` at bindings 0, 1, ... (a buffer, texture view or sampler each)."""
        entries = [{"binding": k, "resource": {"buffer": r} if isinstance(r, wgpu.GPUBuffer) else r}
                   for k, r in enumerate(resources)]
        return self.device.create_bind_group(layout=layout, entries=entries)


def textured_pipelines(device: wgpu.GPUDevice, fmt: str, sample_count: int = 1) -> TexturedPipelines:
    """Made once per device, format and sample count (the device's cache, wgpurender/wgpu_path/device/gpu_cache.py)."""
    return device_cache(device, "textured-pipelines", 16).get(
        (fmt, sample_count), lambda: TexturedPipelines(device, fmt, sample_count))


class Textured(Stage):
    name = "textured"
    summary = "a generated sRGB texture with GPU mipmaps: one combined texture+sampler vs one texture, 4 samplers"

    def setup(self) -> None:
        self._uniforms_written: tuple | None = None  # (size, uv offset) last written: the uniforms change with them
        pipes = self.pipes = textured_pipelines(self.device, self.format, self.msaa)
        self.texture = create_texture(self.ctx, course.pattern_pixels(), srgb=True, mips=True, label="textured-pattern")
        vertices = course.stage_vertices()  # 0..5: the whole plane (left); then 6 per lane (right)
        self.vertex_buffer = self.device.create_buffer_with_data(data=vertices, usage=wgpu.BufferUsage.VERTEX)
        usage = wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST
        self.uniform_buffers = [self.device.create_buffer(size=UNIFORM_SIZE, usage=usage) for _ in range(2)]
        self.uniform_groups = [pipes.group(pipes.uniform_layout, b) for b in self.uniform_buffers]
        # Left: the combined set. Right: the texture set once, and one small set per sampler.
        sampler = create_sampler(self.ctx, course.COMBINED_SAMPLER)
        self.combined_group = pipes.group(pipes.combined_layout, self.texture.view, sampler)
        self.texture_group = pipes.group(pipes.texture_layout, self.texture.view)
        self.sampler_groups = [pipes.group(pipes.sampler_layout, create_sampler(self.ctx, s))
                               for _, s in course.SEPARATE_SAMPLERS]

    def update_uniforms(self, t: float) -> None:
        key = (self.size, tuple(course.uv_offset(t)))
        if key == self._uniforms_written:  # written only when the size or the scroll changes
            return
        self._uniforms_written = key
        height = self.size[1]
        for buffer, (_, w) in zip(self.uniform_buffers, course.halves(self.size[0]), strict=True):
            mvp = course.plane_mvp(max(w, 1) / max(height, 1))
            self.device.queue.write_buffer(buffer, 0, uniform_bytes(mvp, course.uv_offset(t)))

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        self.resize((target.size[0], target.size[1]))
        self.update_uniforms(t)
        height = self.size[1]
        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, course.BACKGROUND)])
        render_pass.set_vertex_buffer(0, self.vertex_buffer)
        (lx, lw), (rx, rw) = course.halves(self.size[0])
        if lw > 0:
            render_pass.set_pipeline(self.pipes.combined)
            render_pass.set_viewport(lx, 0, lw, height, 0.0, 1.0)
            render_pass.set_bind_group(0, self.uniform_groups[0])
            render_pass.set_bind_group(1, self.combined_group)
            render_pass.draw(6)
        if rw > 0:
            render_pass.set_pipeline(self.pipes.separate)
            render_pass.set_viewport(rx, 0, rw, height, 0.0, 1.0)
            render_pass.set_bind_group(0, self.uniform_groups[1])
            render_pass.set_bind_group(1, self.texture_group)  # bound once for all four samplers
            for lane, group in enumerate(self.sampler_groups):
                render_pass.set_bind_group(2, group)
                render_pass.draw(6, 1, 6 * (lane + 1))
        render_pass.end()
