"""Frustum culling on the CPU, for plans whose large draws the GPU cannot cull (core/plan/culling.cpu_culled).

The GPU pass (culling.py) writes a list of visible indices that the vertex shader reads from storage, and needs
compute; with per-instance vertex attributes (core/plan/instance_data.py: OpenGL, GLES) or without compute the
same test runs here, in numpy, when the camera changes (the objects are static): each instance's bounding sphere
(the mesh's, moved by its world matrix and scaled by its largest axis scale, as scene_cull.wgsl does) against
the six frustum planes. The visible instances' Object blocks are written, in scene order, where the draw's
instances start in the scene-objects buffer, and the draw draws that many (scene_pass.py re-records its bundle
when a count changes). The spheres are computed once; a camera step costs one (N, 3) x (3, 6) product per draw.
"""

from __future__ import annotations

import numpy as np
import wgpu

from wgpurender.core.plan import Draw
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.scene.culling import bounding_sphere, frustum_planes


def instance_spheres(worlds: np.ndarray, centre: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) world-space centres and (N,) radii of a mesh's bounding sphere under N world matrices: the radius
    grows by the largest column length of each matrix's 3x3 part (a conservative bound for any scale)."""
    centres = worlds[:, :3, :3] @ np.asarray(centre, np.float64) + worlds[:, :3, 3]
    scale = np.linalg.norm(worlds[:, :3, :3], axis=1).max(axis=1)
    return centres, radius * scale


def visible_mask(planes: np.ndarray, centres: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """(N,) True where a sphere is not wholly outside any plane (n.p + d >= -r for all six; n unit length)."""
    distances = centres @ planes[:, :3].T + planes[:, 3]
    return np.all(distances >= -radii[:, None], axis=1)


class CpuCuller:
    """The CPU-culled draws' spheres and Object blocks, and how many of each draw's instances are drawn now."""

    def __init__(self, ctx: GPUContext, draws: tuple[Draw, ...], meshes, blocks: np.ndarray,
                 object_buffer: wgpu.GPUBuffer) -> None:
        self.ctx, self.buffer = ctx, object_buffer
        self.parts = []
        for d in draws:
            centre, radius = bounding_sphere(meshes.mesh(d.mesh_key).positions)
            centres, radii = instance_spheres(d.world_matrices(), centre, radius)
            own = blocks[d.first_instance: d.first_instance + d.instance_count]
            self.parts.append((d.first_instance, own, centres, radii))
        self.counts = {d.first_instance: d.instance_count for d in draws}

    def update(self, clip_from_world: np.ndarray) -> bool:
        """Cull every draw for this camera and upload the visible blocks; True when a draw's count changed."""
        planes = frustum_planes(clip_from_world)
        changed = False
        for first, own, centres, radii in self.parts:
            visible = own[visible_mask(planes, centres, radii)]
            if len(visible):
                self.ctx.queue.write_buffer(self.buffer, first * own.strides[0], np.ascontiguousarray(visible))
            changed |= self.counts[first] != len(visible)
            self.counts[first] = len(visible)
        return changed

    def count(self, draw: Draw) -> int:
        """How many of ``draw``'s instances are visible (drawn from its first instance on)."""
        return self.counts[draw.first_instance]
