"""The depth-precision scene: two camera-facing planes 0.05% apart at 10 km, near 1 cm, far 100 km.

With the standard depth mapping (0 at near, 1 at far) the stored depth is about 1 - near/|z|: at |z| = 1e4 the two
planes differ by ~5e-10 in depth, far below the step of a 24-bit integer (6e-8) or of a float32 near 1 (6e-8),
so both get the same depth and the draw order decides (z-fighting). Reverse-Z stores about near/|z| instead, a small
number where float32 is dense: the planes differ by 5e-4 relative, which depth32float resolves easily.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu

from numerics.wgsl import load_wgsl
from wgpurender.bench.accuracy_depth import wrong_pixels  # noqa: F401  (re-exported: its one home)
from wgpurender.core.view.transforms import perspective, to_gpu
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.device.targets import create_target, read_texture

NEAR_COLOR = (1.0, 0.0, 0.0, 1.0)  # red: the plane that should win everywhere
FAR_COLOR = (0.0, 1.0, 0.0, 1.0)  # green: seen only where depth failed


@dataclass(frozen=True)
class DepthScene:
    near: float = 0.01
    far: float = 1e5
    distance: float = 1e4  # view-space distance of the nearer plane
    gap: float = 0.0005  # the farther plane is at distance * (1 + gap)
    fov_y_deg: float = 60.0


def _plane_rows(scene: DepthScene, aspect: float, reverse_z: bool, near_first: bool) -> np.ndarray:
    proj = to_gpu(perspective(scene.fov_y_deg, aspect, scene.near, scene.far, reverse_z=reverse_z))
    rows = []
    for z, color in ((-scene.distance, NEAR_COLOR), (-scene.distance * (1 + scene.gap), FAR_COLOR)):
        half = abs(z)  # covers the 60-degree frustum (half-height tan(30) * |z| < |z|)
        rows.append(np.concatenate([proj.reshape(-1), color, [half, z, 0.0, 0.0]]).astype(np.float32))
    return np.stack(rows if near_first else rows[::-1])


def render_planes(
    ctx: GPUContext,
    size: tuple[int, int],
    *,
    depth_format: str = "depth24plus",
    reverse_z: bool = False,
    near_first: bool = False,
    scene: DepthScene = DepthScene(),
) -> np.ndarray:
    """Draw both planes (in the given order) with a depth test; returns the (H, W, 4) uint8 image.

    Standard Z: clear depth 1, compare "less". Reverse-Z: clear depth 0, compare "greater".
    """
    device = ctx.device
    module = create_shader_module(device, "numerics_depth_planes.wgsl", load_wgsl("numerics_depth_planes.wgsl"))
    bgl = device.create_bind_group_layout(
        entries=[{"binding": 0, "visibility": wgpu.ShaderStage.VERTEX, "buffer": {"type": "read-only-storage"}}]
    )
    pipeline = device.create_render_pipeline(
        label="depth-planes",
        layout=device.create_pipeline_layout(bind_group_layouts=[bgl]),
        vertex={"module": module, "entry_point": "vs_main", "buffers": []},
        primitive={"topology": "triangle-list", "cull_mode": "none"},
        depth_stencil={
            "format": depth_format,
            "depth_write_enabled": True,
            "depth_compare": "greater" if reverse_z else "less",
        },
        multisample={"count": 1},
        fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": "rgba8unorm"}]},
    )
    rows = _plane_rows(scene, size[0] / size[1], reverse_z, near_first)
    buffer = device.create_buffer_with_data(data=rows, usage=wgpu.BufferUsage.STORAGE)
    bind_group = device.create_bind_group(
        layout=bgl, entries=[{"binding": 0, "resource": {"buffer": buffer, "offset": 0, "size": buffer.size}}]
    )
    color = create_target(ctx, size, "rgba8unorm", label="depth-planes-color")
    depth = device.create_texture(
        size=(size[0], size[1], 1), format=depth_format, usage=wgpu.TextureUsage.RENDER_ATTACHMENT
    )
    encoder = device.create_command_encoder()
    render_pass = encoder.begin_render_pass(
        color_attachments=[
            {"view": color.create_view(), "load_op": "clear", "clear_value": (0, 0, 0, 1), "store_op": "store"}
        ],
        depth_stencil_attachment={
            "view": depth.create_view(),
            "depth_clear_value": 0.0 if reverse_z else 1.0,
            "depth_load_op": "clear",
            "depth_store_op": "discard",
        },
    )
    render_pass.set_pipeline(pipeline)
    render_pass.set_bind_group(0, bind_group)
    for instance in range(2):  # two draws: the order is the point
        render_pass.draw(6, 1, 0, instance)
    render_pass.end()
    ctx.queue.submit([encoder.finish()])
    return read_texture(ctx, color)


def stored_depth(z_view: float, scene: DepthScene = DepthScene(), *, reverse_z: bool = False) -> float:
    """The depth value the mapping gives a view-space z, in float64 (for the docs and the analytic check)."""
    proj = perspective(scene.fov_y_deg, 1.0, scene.near, scene.far, reverse_z=reverse_z)
    clip = proj @ np.array([0.0, 0.0, z_view, 1.0])
    return float(clip[2] / clip[3])
