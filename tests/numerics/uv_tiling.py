"""Huge UV tiling: wrap UVs per vertex in float64 before the GPU interpolates them in float32.

A terrain tiled 1e4 times has UVs up to 1e4 at its far end. float32 spacing at 1e4 is 2^-10 ~ 1e-3, so the
rasteriser's float32 interpolation of such UVs (and the sampler's own wrap) lands on a grid of 1/1000 of a repeat:
a quarter texel of a 256-texel texture, visible as stair-stepped, swimming texels. Repeat addressing only depends
on the fractional part, and shifting all of a mesh's (or a triangle's) UVs by the same integer changes nothing in
exact arithmetic, so the shift is done on the CPU in float64 and the GPU only ever sees small UVs.
"""

from __future__ import annotations

import numpy as np
import wgpu

from numerics.wgsl import load_wgsl
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.device.targets import create_target, read_texture


def wrap_uvs(uvs: np.ndarray) -> np.ndarray:
    """UVs minus the integer part of their minimum (per component), float64 -> float32.

    Pass one mesh or one connected patch at a time: the same shift for all of its vertices keeps the
    differences between neighbours (which interpolation uses) exact.
    """
    uv = np.asarray(uvs, dtype=np.float64)
    return (uv - np.floor(uv.min(axis=0))).astype(np.float32)


def index_texture(ctx: GPUContext, size: int) -> wgpu.GPUTexture:
    """A size x size rgba32float texture whose texel (x, y) holds (x, y, 0, 1)."""
    ys, xs = np.mgrid[0:size, 0:size].astype(np.float32)
    data = np.stack([xs, ys, np.zeros_like(xs), np.ones_like(xs)], axis=-1)
    texture = ctx.device.create_texture(
        size=(size, size, 1),
        format="rgba32float",
        usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST,
    )
    ctx.queue.write_texture(
        {"texture": texture, "mip_level": 0, "origin": (0, 0, 0)},
        np.ascontiguousarray(data),
        {"offset": 0, "bytes_per_row": size * 16, "rows_per_image": size},
        (size, size, 1),
    )
    return texture


def render_uv_probe(
    ctx: GPUContext, size: tuple[int, int], corner_uvs: np.ndarray, texture_size: int = 256
) -> np.ndarray:
    """A viewport-filling quad with float32 UVs at its corners (top-left, top-right, bottom-left, bottom-right).

    Returns (H, W, 4) float32: texel coordinate fract(uv) * texture_size (x, y) and the fetched texel (x, y).
    """
    device = ctx.device
    module = create_shader_module(device, "numerics_uv.wgsl", load_wgsl("numerics_uv.wgsl"))
    ndc = np.array([[-1, 1], [1, 1], [-1, -1], [1, -1]], dtype=np.float32)
    corners = np.concatenate([ndc, np.asarray(corner_uvs, dtype=np.float32)], axis=1)
    vertices = np.ascontiguousarray(corners[[0, 2, 1, 1, 2, 3]])
    pipeline = device.create_render_pipeline(
        label="numerics-uv",
        layout="auto",
        vertex={
            "module": module,
            "entry_point": "vs_main",
            "buffers": [
                {
                    "array_stride": 16,
                    "attributes": [
                        {"format": "float32x2", "offset": 0, "shader_location": 0},
                        {"format": "float32x2", "offset": 8, "shader_location": 1},
                    ],
                }
            ],
        },
        primitive={"topology": "triangle-list", "cull_mode": "none"},
        multisample={"count": 1},
        fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": "rgba32float"}]},
    )
    sampler = device.create_sampler(
        mag_filter="nearest", min_filter="nearest", address_mode_u="repeat", address_mode_v="repeat"
    )
    bind_group = device.create_bind_group(
        layout=pipeline.get_bind_group_layout(0),
        entries=[
            {"binding": 0, "resource": index_texture(ctx, texture_size).create_view()},
            {"binding": 1, "resource": sampler},
        ],
    )
    buffer = device.create_buffer_with_data(data=vertices, usage=wgpu.BufferUsage.VERTEX)
    target = create_target(ctx, size, "rgba32float", label="numerics-uv")
    encoder = device.create_command_encoder()
    render_pass = encoder.begin_render_pass(
        color_attachments=[
            {"view": target.create_view(), "load_op": "clear", "clear_value": (0, 0, 0, 0), "store_op": "store"}
        ]
    )
    render_pass.set_pipeline(pipeline)
    render_pass.set_bind_group(0, bind_group)
    render_pass.set_vertex_buffer(0, buffer)
    render_pass.draw(6)
    render_pass.end()
    ctx.queue.submit([encoder.finish()])
    return read_texture(ctx, target)


def exact_uvs(size: tuple[int, int], corner_uvs: np.ndarray) -> np.ndarray:
    """float64 UVs at the pixel centres of the quad of :func:`render_uv_probe` (bilinear = affine here)."""
    w, h = size
    c = np.asarray(corner_uvs, dtype=np.float64)
    fx = (np.arange(w) + 0.5) / w
    fy = (np.arange(h) + 0.5) / h
    top = c[0] + fx[:, None] * (c[1] - c[0])  # (W, 2)
    left_to_bottom = c[2] - c[0]
    return top[None, :, :] + fy[:, None, None] * left_to_bottom[None, None, :]  # (H, W, 2)
