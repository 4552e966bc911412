"""Flat-colour triangles at 1x or 4x MSAA, read back as per-pixel coverage (0..1), for coverage-vs-area tests.

A pixel's resolved value is (covered samples) / (sample count): at 1x a sub-pixel triangle covers its pixel
fully or not at all (it is there only if it contains the pixel centre), at 4x in quarters. The target is
rgba16float, which holds k/4 exactly, so the coverage is read back without quantisation.
"""

from __future__ import annotations

import numpy as np
import wgpu

from numerics.wgsl import load_wgsl
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.device.targets import create_target, read_texture

FORMAT = "rgba16float"


def pixels_to_ndc(points_px: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Pixel coordinates (x right, y down, origin top-left) to wgpu NDC (y up), float64."""
    p = np.asarray(points_px, dtype=np.float64)
    return np.stack([p[..., 0] / size[0] * 2 - 1, 1 - p[..., 1] / size[1] * 2], axis=-1)


def render_coverage(ctx: GPUContext, size: tuple[int, int], triangles_px: np.ndarray, sample_count: int) -> np.ndarray:
    """Draw (N, 3, 2) pixel-space triangles white on black; returns the (H, W) float64 coverage image."""
    device = ctx.device
    module = create_shader_module(device, "numerics_coverage.wgsl", load_wgsl("numerics_coverage.wgsl"))
    pipeline = device.create_render_pipeline(
        label=f"coverage-{sample_count}x",
        layout=device.create_pipeline_layout(bind_group_layouts=[]),
        vertex={
            "module": module,
            "entry_point": "vs_main",
            "buffers": [
                {"array_stride": 8, "attributes": [{"format": "float32x2", "offset": 0, "shader_location": 0}]}
            ],
        },
        primitive={"topology": "triangle-list", "cull_mode": "none"},
        multisample={"count": sample_count},
        fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": FORMAT}]},
    )
    vertices = pixels_to_ndc(triangles_px, size).astype(np.float32).reshape(-1, 2)
    buffer = device.create_buffer_with_data(data=vertices, usage=wgpu.BufferUsage.VERTEX)
    resolved = create_target(ctx, size, FORMAT, label="coverage")
    attachment = {"load_op": "clear", "clear_value": (0, 0, 0, 0), "store_op": "store"}
    if sample_count > 1:
        msaa = create_target(ctx, size, FORMAT, sample_count=sample_count, label="coverage-msaa")
        attachment |= {"view": msaa.create_view(), "resolve_target": resolved.create_view(), "store_op": "discard"}
    else:
        attachment |= {"view": resolved.create_view()}
    encoder = device.create_command_encoder()
    render_pass = encoder.begin_render_pass(color_attachments=[attachment])
    render_pass.set_pipeline(pipeline)
    render_pass.set_vertex_buffer(0, buffer)
    render_pass.draw(len(vertices))
    render_pass.end()
    ctx.queue.submit([encoder.finish()])
    return read_texture(ctx, resolved)[..., 0].astype(np.float64)


def triangle_areas(triangles_px: np.ndarray) -> np.ndarray:
    """Analytic areas (float64, pixels^2) of (N, 3, 2) triangles."""
    t = np.asarray(triangles_px, dtype=np.float64)
    e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def cell_sums(coverage: np.ndarray, cell: int) -> np.ndarray:
    """Coverage summed over each cell x cell block, row-major: one value per triangle when each has its own cell."""
    h, w = coverage.shape
    return coverage.reshape(h // cell, cell, w // cell, cell).sum(axis=(1, 3)).reshape(-1)
