"""GPU frustum culling of the plan's culled draws (core/plan/culling.py decides which; shaders_wgsl/scene_cull.wgsl).

When the camera changes (scene_pass.py; the objects are static), before the scene pass: the indirect argument
blocks are reset (``queue.write_buffer``: index count,
instance_count 0, first index, base vertex, first instance), one compute pass dispatches one invocation per
instance of each culled draw, and the scene pass draws each with ``draw_indexed_indirect`` (recorded once in the
bundle: only the buffer's contents change). The frustum planes are written when the camera changes.
"""

from __future__ import annotations

import numpy as np
import wgpu

from wgpurender.core.plan import Draw, RenderPlan
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module

SHADER = "scene_cull.wgsl"
CULL_BYTES = 6 * 16 + 16 + 16  # planes, sphere, first/count/args/pad
ARGS_BYTES = 20  # draw_indexed_indirect: index_count, instance_count, first_index, base_vertex, first_instance
WORKGROUP = 64


def frustum_planes(clip_from_world: np.ndarray) -> np.ndarray:
    """(6, 4) planes (n, d), n pointing inwards and unit length: n.p + d >= 0 inside. Rows of the clip matrix
    (Gribb and Hartmann): x and y within +-w, and 0 <= z <= w (WebGPU's depth range; reversed depth gives the
    same two planes the other way round). An infinite projection's far plane comes out as (0, 0, 0, near):
    no normal, every point inside; it is kept as it is (dividing by its zero length would make it NaN, and a
    NaN plane culls everything)."""
    r = np.asarray(clip_from_world, dtype=np.float64)
    planes = np.array([r[3] + r[0], r[3] - r[0], r[3] + r[1], r[3] - r[1], r[2], r[3] - r[2]])
    lengths = np.linalg.norm(planes[:, :3], axis=1, keepdims=True)
    return planes / np.where(lengths > 0, lengths, 1.0)


def bounding_sphere(positions: np.ndarray) -> tuple[np.ndarray, float]:
    """The centre of the bounding box and the largest distance from it to a vertex: a sphere around the mesh."""
    p = np.asarray(positions, dtype=np.float64)
    centre = (p.min(axis=0) + p.max(axis=0)) / 2
    return centre, float(np.linalg.norm(p - centre, axis=1).max())


class GpuCuller:
    """Buffers, pipeline and bind groups of the culling pass; ``visible`` and ``indirect`` are read by the draws."""

    def __init__(self, ctx: GPUContext, plan: RenderPlan, meshes, object_buffer: wgpu.GPUBuffer, total: int) -> None:
        self.ctx, self.draws = ctx, plan.culled_draws
        dev = ctx.device
        storage = wgpu.BufferUsage.STORAGE
        self.visible = dev.create_buffer(label="scene-visible", size=4 * max(total, 1), usage=storage)
        self.indirect = dev.create_buffer(label="scene-indirect", size=ARGS_BYTES * len(self.draws),
                                          usage=wgpu.BufferUsage.INDIRECT | storage | wgpu.BufferUsage.COPY_DST
                                          | wgpu.BufferUsage.COPY_SRC)
        self.stride = -(-CULL_BYTES // ctx.limit("min-uniform-buffer-offset-alignment")) * ctx.limit(
            "min-uniform-buffer-offset-alignment")
        self.cull = dev.create_buffer(label="scene-cull", size=self.stride * len(self.draws),
                                      usage=wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST)
        self.args = np.zeros((len(self.draws), 5), np.uint32)
        self.spheres = []
        for k, d in enumerate(self.draws):
            first_index, count = meshes.index_range(d)
            self.args[k] = (count, 0, first_index, 0, d.first_instance)
            self.spheres.append(bounding_sphere(meshes.mesh(d.mesh_key).positions))
        self._make_pipeline(object_buffer)

    def _make_pipeline(self, object_buffer: wgpu.GPUBuffer) -> None:
        dev, comp = self.ctx.device, wgpu.ShaderStage.COMPUTE
        entries = [{"binding": 0, "visibility": comp, "buffer": {"type": "read-only-storage"}},
                   {"binding": 1, "visibility": comp, "buffer": {"type": "storage"}},
                   {"binding": 2, "visibility": comp, "buffer": {"type": "storage"}},
                   {"binding": 3, "visibility": comp, "buffer": {"type": "uniform", "min_binding_size": CULL_BYTES}}]
        layout = dev.create_bind_group_layout(label="cull", entries=entries)
        self.pipeline = dev.create_compute_pipeline(
            label="scene-cull", layout=dev.create_pipeline_layout(label="cull", bind_group_layouts=[layout]),
            compute={"module": create_shader_module(dev, SHADER), "entry_point": "cs_cull"})
        self.groups = [dev.create_bind_group(label=f"cull {d.label}", layout=layout, entries=[
            {"binding": 0, "resource": {"buffer": object_buffer}},
            {"binding": 1, "resource": {"buffer": self.visible}},
            {"binding": 2, "resource": {"buffer": self.indirect}},
            {"binding": 3, "resource": {"buffer": self.cull, "offset": k * self.stride, "size": CULL_BYTES}}])
            for k, d in enumerate(self.draws)]

    def write_planes(self, clip_from_world: np.ndarray) -> None:
        """Each draw's Cull block for this camera (written when the camera changes)."""
        planes = frustum_planes(clip_from_world).astype(np.float32)
        data = bytearray(self.stride * len(self.draws))
        for k, (d, (centre, radius)) in enumerate(zip(self.draws, self.spheres, strict=True)):
            block = np.zeros(CULL_BYTES // 4, np.float32)
            block[:24] = planes.reshape(-1)
            block[24:28] = (*centre, radius)
            block[28:32].view(np.uint32)[:] = (d.first_instance, d.instance_count, k * 5 + 1, 0)
            data[k * self.stride: k * self.stride + CULL_BYTES] = block.tobytes()
        self.ctx.queue.write_buffer(self.cull, 0, bytes(data))

    def record(self, encoder: wgpu.GPUCommandEncoder) -> None:
        """Reset the instance counts and run the culling pass (before the scene pass reads the results)."""
        self.ctx.queue.write_buffer(self.indirect, 0, self.args.tobytes())
        cpass = encoder.begin_compute_pass(label="scene-cull")
        cpass.set_pipeline(self.pipeline)
        for group, d in zip(self.groups, self.draws, strict=True):
            cpass.set_bind_group(0, group)
            cpass.dispatch_workgroups(-(-d.instance_count // WORKGROUP))
        cpass.end()

    def offset(self, draw: Draw) -> int:
        """The byte offset of ``draw``'s indirect block."""
        return ARGS_BYTES * next(k for k, d in enumerate(self.draws) if d.first_instance == draw.first_instance)
