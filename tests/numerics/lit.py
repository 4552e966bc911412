"""A lit, normal-mapped mesh rendered into a float target: where NaN/inf from degenerate input would show.

Unorm targets clamp (NaN usually becomes 0), hiding the problem; rgba32float stores whatever the shader
computed. ``safe=False`` selects plain WGSL ``normalize`` (the counter-example) through an override constant.
"""

from __future__ import annotations

import numpy as np
import wgpu

from numerics.wgsl import load_wgsl
from wgpurender.core.view.transforms import to_gpu
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.device.targets import create_target, read_texture

SHADERS = ("numerics_safe.wgsl", "numerics_lit.wgsl")
FORMAT = "rgba32float"
CLEAR = (0.0, 0.0, 0.0, 0.0)
VERTEX_LAYOUT = {
    "array_stride": 48,
    "attributes": [
        {"format": "float32x3", "offset": 0, "shader_location": 0},
        {"format": "float32x3", "offset": 12, "shader_location": 1},
        {"format": "float32x4", "offset": 24, "shader_location": 2},
        {"format": "float32x2", "offset": 40, "shader_location": 3},
    ],
}


def interleave(positions, normals, tangents, uvs) -> np.ndarray:
    """(N, 12) float32 vertices: position, normal, tangent (xyzw), uv; NaN/inf passed through untouched."""
    parts = [np.asarray(a, dtype=np.float32).reshape(len(positions), -1) for a in (positions, normals, tangents, uvs)]
    return np.ascontiguousarray(np.concatenate(parts, axis=1))


def render_lit(
    ctx: GPUContext,
    size: tuple[int, int],
    vertices: np.ndarray,
    indices: np.ndarray,
    clip_from_model: np.ndarray,
    normal_matrix: np.ndarray,
    *,
    light_dir=(0.3, 0.5, 0.81),
    safe: bool = True,
) -> np.ndarray:
    """Draw an indexed mesh (vertices from :func:`interleave`); returns the (H, W, 4) float32 image."""
    device = ctx.device
    code = "\n".join(load_wgsl(n) for n in SHADERS)
    module = create_shader_module(device, SHADERS[-1], code)
    bgl = device.create_bind_group_layout(
        entries=[
            {
                "binding": 0,
                "visibility": wgpu.ShaderStage.VERTEX | wgpu.ShaderStage.FRAGMENT,
                "buffer": {"type": "uniform"},
            }
        ]
    )
    pipeline = device.create_render_pipeline(
        label=f"numerics-lit-{'safe' if safe else 'naive'}",
        layout=device.create_pipeline_layout(bind_group_layouts=[bgl]),
        vertex={"module": module, "entry_point": "vs_main", "buffers": [VERTEX_LAYOUT]},
        primitive={"topology": "triangle-list", "cull_mode": "none"},
        multisample={"count": 1},
        fragment={
            "module": module,
            "entry_point": "fs_main",
            "targets": [{"format": FORMAT}],
            "constants": {"SAFE": 1 if safe else 0},
        },
    )
    n4 = np.eye(4)
    n4[:3, :3] = np.asarray(normal_matrix, dtype=np.float64)[:3, :3]
    light = np.asarray(light_dir, dtype=np.float64)
    uniforms = np.concatenate(
        [to_gpu(clip_from_model).reshape(-1), to_gpu(n4).reshape(-1), light / np.linalg.norm(light), [0.0]]
    ).astype(np.float32)
    ubuf = device.create_buffer_with_data(data=uniforms, usage=wgpu.BufferUsage.UNIFORM)
    vbuf = device.create_buffer_with_data(data=np.asarray(vertices, np.float32), usage=wgpu.BufferUsage.VERTEX)
    idx = np.asarray(indices, dtype=np.uint32).reshape(-1)
    ibuf = device.create_buffer_with_data(data=idx, usage=wgpu.BufferUsage.INDEX)
    bind_group = device.create_bind_group(
        layout=bgl, entries=[{"binding": 0, "resource": {"buffer": ubuf, "offset": 0, "size": ubuf.size}}]
    )
    target = create_target(ctx, size, FORMAT, label="numerics-lit")
    encoder = device.create_command_encoder()
    render_pass = encoder.begin_render_pass(
        color_attachments=[
            {"view": target.create_view(), "load_op": "clear", "clear_value": CLEAR, "store_op": "store"}
        ]
    )
    render_pass.set_pipeline(pipeline)
    render_pass.set_bind_group(0, bind_group)
    render_pass.set_vertex_buffer(0, vbuf)
    render_pass.set_index_buffer(ibuf, "uint32")
    render_pass.draw_indexed(len(idx))
    render_pass.end()
    ctx.queue.submit([encoder.finish()])
    return read_texture(ctx, target)
