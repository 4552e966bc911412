"""Course step 5: textures and samplers, combined and separate, on a plane seen at a grazing angle.

Left half: the plane drawn with its texture and its own sampler in ONE bind group
(the combined image sampler of the course). Right half: the same plane cut into
four lanes along its length, ONE texture bound once and four samplers swapped
between the lanes' draws (separate sampled image + samplers), from left to right:
nearest without mips, bilinear without mips, trilinear, trilinear with 16x
anisotropy. Far away the first two alias (moire), trilinear blurs, anisotropic
stays sharp.

The texture is generated (:func:`pattern_pixels`), uploaded as rgba8unorm-srgb and
gets a gamma-correct mip chain on the GPU (wgpurender/textures.py).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import wgpu

from ..gpu import GPUContext
from ..gpu_cache import device_cache
from ..shaders import create_shader_module
from ..textures import (
    BILINEAR,
    NEAREST,
    TRILINEAR,
    SamplerSpec,
    Texture,
    anisotropic,
    create_sampler,
    create_texture,
)
from ..transforms import look_at, perspective, to_gpu
from .base import Stage

VERTEX_LAYOUT = {
    "array_stride": 5 * 4,
    "step_mode": "vertex",
    "attributes": [
        {"shader_location": 0, "format": "float32x3", "offset": 0},
        {"shader_location": 1, "format": "float32x2", "offset": 3 * 4},
    ],
}
UNIFORM_SIZE = 64 + 16  # mat4x4f mvp, vec4f uv_offset
BACKGROUND = (0.02, 0.03, 0.06, 1.0)

# The ground plane: y = 0, x in [-2, 2], z from 3 (near, below the view) to -60 (far); the texture
# repeats every 2 units both ways, so texels stay square on the plane. On the right
# it is cut into 4 lanes along x with LANE_GAP units of background between them.
PLANE_X = (-2.0, 2.0)
PLANE_Z = (3.0, -60.0)
TILE = 2.0
LANE_GAP = 0.1
EYE, LOOK_AT = (0.0, 0.8, 3.5), (0.0, 0.0, -8.0)
FOV_Y = 50.0
SCROLL_PER_SECOND = 0.25  # texture repeats per second along the plane

COMBINED_SAMPLER = SamplerSpec(max_anisotropy=16, address_mode_u="mirror-repeat", address_mode_v="mirror-repeat")
SEPARATE_SAMPLERS: tuple[tuple[str, SamplerSpec], ...] = (
    ("nearest, no mips", dataclasses.replace(NEAREST, lod_max_clamp=0.0)),
    ("bilinear, no mips", dataclasses.replace(BILINEAR, lod_max_clamp=0.0)),
    ("trilinear", TRILINEAR),
    ("trilinear + 16x anisotropic", anisotropic(16)),
)


def pattern_pixels(size: int = 256, cells: int = 8) -> np.ndarray:
    """The generated colour texture (sRGB bytes): a checker of white and a colour gradient, with dark grid lines.

    Thin lines and sharp edges are what filtering changes most visibly.
    """
    y, x = np.mgrid[0:size, 0:size].astype(np.float64) / (size - 1)
    cell = size // cells
    iy, ix = np.mgrid[0:size, 0:size]
    dark = ((ix // cell) + (iy // cell)) % 2 == 1
    rgb = np.empty((size, size, 3))
    rgb[..., 0] = 0.15 + 0.8 * x
    rgb[..., 1] = 0.25 + 0.6 * y
    rgb[..., 2] = 0.85 - 0.6 * x
    rgb[~dark] = 0.95
    line = ((ix % cell) < 2) | ((iy % cell) < 2)
    rgb[line] = 0.05
    pixels = np.empty((size, size, 4), dtype=np.uint8)
    pixels[..., :3] = np.round(rgb * 255)
    pixels[..., 3] = 255
    return pixels


def quad_vertices(corners: np.ndarray, uv_rect=(0.0, 0.0, 1.0, 1.0)) -> np.ndarray:
    """Two triangles from 4 corners (top-left, top-right, bottom-left, bottom-right) as (6, 5) float32.

    uv (u0, v0) goes to the top-left corner and (u1, v1) to the bottom-right.
    """
    u0, v0, u1, v1 = uv_rect
    uvs = np.array([[u0, v0], [u1, v0], [u0, v1], [u1, v1]])
    verts = np.hstack([np.asarray(corners, dtype=np.float64), uvs])
    return verts[[0, 2, 1, 1, 2, 3]].astype(np.float32)


# A screen-aligned quad filling NDC, uv (0,0) at the top-left pixel: with an identity mvp one texel
# of an n-texel texture covers exactly size/n pixels.
SCREEN_QUAD = quad_vertices(np.array([[-1, 1, 0], [1, 1, 0], [-1, -1, 0], [1, -1, 0]]))


def plane_vertices(x_range=PLANE_X) -> np.ndarray:
    """The plane (or a lane of it) between x_range; uv follow world x and z, so lanes continue the pattern."""
    x0, x1 = x_range
    z0, z1 = PLANE_Z
    corners = np.array([[x0, 0, z1], [x1, 0, z1], [x0, 0, z0], [x1, 0, z0]])  # far edge at the top
    u0 = (x0 - PLANE_X[0]) / TILE
    return quad_vertices(corners, (u0, 0.0, u0 + (x1 - x0) / TILE, (z0 - z1) / TILE))


def lane_ranges(count: int, gap: float = LANE_GAP) -> list[tuple[float, float]]:
    """x ranges of ``count`` equal lanes across the plane, ``gap`` apart."""
    x0, x1 = PLANE_X
    width = (x1 - x0) / count
    ranges = []
    for i in range(count):
        left = x0 + i * width + (gap / 2 if i > 0 else 0.0)
        right = x0 + (i + 1) * width - (gap / 2 if i < count - 1 else 0.0)
        ranges.append((left, right))
    return ranges


def plane_mvp(aspect: float) -> np.ndarray:
    return perspective(FOV_Y, aspect, 0.05, 100.0) @ look_at(EYE, LOOK_AT)


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

    def uniform_group(self, buffer: wgpu.GPUBuffer) -> wgpu.GPUBindGroup:
        return self.device.create_bind_group(
            layout=self.uniform_layout, entries=[{"binding": 0, "resource": {"buffer": buffer}}]
        )

    def combined_group(self, view: wgpu.GPUTextureView, sampler: wgpu.GPUSampler) -> wgpu.GPUBindGroup:
        return self.device.create_bind_group(
            layout=self.combined_layout,
            entries=[{"binding": 0, "resource": view}, {"binding": 1, "resource": sampler}],
        )

    def texture_group(self, view: wgpu.GPUTextureView) -> wgpu.GPUBindGroup:
        return self.device.create_bind_group(layout=self.texture_layout, entries=[{"binding": 0, "resource": view}])

    def sampler_group(self, sampler: wgpu.GPUSampler) -> wgpu.GPUBindGroup:
        return self.device.create_bind_group(layout=self.sampler_layout, entries=[{"binding": 0, "resource": sampler}])


def textured_pipelines(device: wgpu.GPUDevice, fmt: str, sample_count: int = 1) -> TexturedPipelines:
    """Made once per device, format and sample count (the device's cache, wgpurender/gpu_cache.py)."""
    return device_cache(device, "textured-pipelines", 16).get(
        (fmt, sample_count), lambda: TexturedPipelines(device, fmt, sample_count))


def render_textured(
    ctx: GPUContext,
    target: wgpu.GPUTexture,
    texture: Texture,
    sampler: SamplerSpec,
    vertices: np.ndarray = SCREEN_QUAD,
    mvp: np.ndarray | None = None,
    clear=BACKGROUND,
) -> None:
    """Draw ``vertices`` with ``texture`` through ``sampler`` into a single-sample target and submit.

    For tests and tools: the separate-sampler pipeline, identity mvp by default.
    """
    device = ctx.device
    pipes = textured_pipelines(device, target.format, 1)
    uniforms = uniform_bytes(np.eye(4) if mvp is None else mvp)
    ubuf = device.create_buffer_with_data(data=uniforms, usage=wgpu.BufferUsage.UNIFORM)
    vertex_data = np.ascontiguousarray(vertices, dtype=np.float32)
    vbuf = device.create_buffer_with_data(data=vertex_data, usage=wgpu.BufferUsage.VERTEX)
    encoder = device.create_command_encoder(label="render-textured")
    attachment = {"view": target.create_view(), "clear_value": clear, "load_op": "clear", "store_op": "store"}
    render_pass = encoder.begin_render_pass(color_attachments=[attachment])
    render_pass.set_pipeline(pipes.separate)
    render_pass.set_bind_group(0, pipes.uniform_group(ubuf))
    render_pass.set_bind_group(1, pipes.texture_group(texture.view))
    render_pass.set_bind_group(2, pipes.sampler_group(create_sampler(ctx, sampler)))
    render_pass.set_vertex_buffer(0, vbuf)
    render_pass.draw(len(vertices))
    render_pass.end()
    ctx.queue.submit([encoder.finish()])


class Textured(Stage):
    name = "textured"
    summary = "a generated sRGB texture with GPU mipmaps: one combined texture+sampler vs one texture, 4 samplers"
    course_step = "5: textures, combined or separate (texture + one or several samplers)"
    order = 5.0
    supports_msaa = True

    def setup(self) -> None:
        self.pipes = textured_pipelines(self.device, self.format, self.msaa)
        self.texture = create_texture(self.ctx, pattern_pixels(), srgb=True, mips=True, label="textured-pattern")
        # Vertices 0..5: the whole plane (left); then 6 per lane (right).
        lanes = [plane_vertices(r) for r in lane_ranges(len(SEPARATE_SAMPLERS))]
        vertices = np.concatenate([plane_vertices(), *lanes])
        self.vertex_buffer = self.device.create_buffer_with_data(data=vertices, usage=wgpu.BufferUsage.VERTEX)
        usage = wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST
        self.uniform_buffers = [self.device.create_buffer(size=UNIFORM_SIZE, usage=usage) for _ in range(2)]
        self.uniform_groups = [self.pipes.uniform_group(b) for b in self.uniform_buffers]
        # Left: the combined set. Right: the texture set once, and one small set per sampler.
        self.combined_group = self.pipes.combined_group(self.texture.view, create_sampler(self.ctx, COMBINED_SAMPLER))
        self.texture_group = self.pipes.texture_group(self.texture.view)
        self.sampler_groups = [self.pipes.sampler_group(create_sampler(self.ctx, s)) for _, s in SEPARATE_SAMPLERS]

    def halves(self) -> tuple[tuple[int, int], tuple[int, int]]:
        """(x, width) of the left and right viewports."""
        width = self.size[0]
        left = width // 2
        return (0, left), (left, width - left)

    def draw(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        self.resize((target.size[0], target.size[1]))
        height = self.size[1]
        uv_offset = (0.0, -SCROLL_PER_SECOND * t)
        for buffer, (_, w) in zip(self.uniform_buffers, self.halves(), strict=True):
            mvp = plane_mvp(max(w, 1) / max(height, 1))
            self.device.queue.write_buffer(buffer, 0, uniform_bytes(mvp, uv_offset))

        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, BACKGROUND)])
        render_pass.set_vertex_buffer(0, self.vertex_buffer)
        (lx, lw), (rx, rw) = self.halves()
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
