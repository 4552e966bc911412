"""GPU resources of a scene's models and materials: meshes, vertex/index buffers, textures, samplers.

Built from the render plan only: a texture is uploaded when the plan lists it (in the format and
with the mip chain it says), a vertex buffer holds exactly the attributes of the variant that
draws it. Everything is cached, so models sharing a mesh file or a texture share the GPU copy.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import wgpu

from wgpurender.core.plan import Draw, RenderPlan
from wgpurender.core.plan.meshes import PlanMeshes, buffer_places
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.textures import Texture, create_sampler, create_texture
from wgpurender.wgpu_path.scene.shader_interface import interleave


@dataclass(frozen=True)
class MeshBuffers:
    """A mesh on the GPU, interleaved for one attribute set: its bytes from ``vertex_offset`` and
    ``index_offset`` of buffers it may share with the scene's other meshes (:meth:`SceneResources.upload_meshes`)."""

    vertex: wgpu.GPUBuffer
    index: wgpu.GPUBuffer
    index_format: str
    index_count: int
    vertex_offset: int = 0
    index_offset: int = 0
    base_vertex: int = 0  # vertex_offset in vertices of this mesh's stride (a draw from the buffers bound at 0)
    first_index: int = 0  # index_offset in indices of index_format


class SceneResources:
    """Meshes, buffers, textures and samplers of one plan (created on first use, then cached)."""

    def __init__(self, ctx: GPUContext, plan: RenderPlan) -> None:
        self.ctx = ctx
        self.plan = plan
        self.meshes = PlanMeshes(plan)  # what is loaded and checked: the core's, as on the raw path
        self._buffers: dict[tuple[Path, tuple[str, ...]], MeshBuffers] = {}
        self._textures: dict[tuple[Path, str], Texture] = {}
        self._mipmaps = {(t.path, t.format): t.mipmaps for t in plan.textures}

    # -- meshes ----------------------------------------------------------------
    def upload_meshes(self, draws) -> None:
        """The meshes of ``draws`` not on the GPU yet, in ONE vertex and ONE index buffer, each mesh's vertices
        starting on a whole vertex of its stride (so a draw names it by ``base_vertex`` with the buffers bound at
        0) and at 4-byte aligned offsets (set_vertex_buffer's and set_index_buffer's rule): a scene of 10k mesh
        files made 20k buffers before, each several wgpu calls (issue 31.3). Where the device's max-buffer-size
        would be passed, the next meshes go into another pair (core/plan/meshes.buffer_places; one mesh too large
        for it is refused in one line). Draw order decides the layout; a draw whose mesh fails its variant's check
        (mesh_for) raises here, as it did when its buffers were made one by one."""
        pending: dict[tuple, tuple[bytes, bytes, object]] = {}
        for draw in draws:
            key = (draw.mesh_key, self.plan.variant(draw.variant_key).vertex_attributes)
            if key not in self._buffers and key not in pending:
                mesh = self.meshes.mesh_for(draw)
                pending[key] = (interleave(mesh, key[1]).tobytes(), mesh.index_bytes(), mesh)
        if not pending:
            return
        names = [key[0][0].name for key in pending]  # key[0]: the draw's mesh_key, (file, pose)
        strides = [len(v) // mesh.vertex_count for v, _, mesh in pending.values()]
        places = buffer_places([(len(v), len(i)) for v, i, _ in pending.values()],
                               self.ctx.limit("max-buffer-size"), names, strides)
        pairs: dict[int, tuple[bytearray, bytearray]] = {}
        for (vertices, indices, _), (pair, v_at, _) in zip(pending.values(), places, strict=True):
            vertex, index = pairs.setdefault(pair, (bytearray(), bytearray()))
            vertex += b"\0" * (v_at - len(vertex))  # up to its place: a whole vertex of its stride
            vertex += vertices
            index += indices  # index_bytes is already a multiple of 4
        for vertex, _ in pairs.values():
            vertex += b"\0" * (-len(vertex) % 4)  # float32 strides keep it whole; the buffer's size rule, stated
        dev = self.ctx.device
        # named as the plan lists them (RenderPlan.buffers)
        made = {pair: (dev.create_buffer_with_data(data=vertex, usage=wgpu.BufferUsage.VERTEX, label="scene-vertices"),
                       dev.create_buffer_with_data(data=index, usage=wgpu.BufferUsage.INDEX, label="scene-indices"))
                for pair, (vertex, index) in pairs.items()}
        for (key, (_, _, mesh)), (pair, v_at, i_at), stride in zip(pending.items(), places, strides, strict=True):
            self._buffers[key] = MeshBuffers(*made[pair], mesh.index_format, mesh.indices.size, v_at, i_at,
                                             v_at // stride, i_at // mesh.indices.itemsize)

    def mesh_buffers(self, draw: Draw) -> MeshBuffers:
        """The draw's mesh on the GPU (uploaded now, alone, unless :meth:`upload_meshes` did already)."""
        key = (draw.mesh_key, self.plan.variant(draw.variant_key).vertex_attributes)
        if key not in self._buffers:
            self.upload_meshes([draw])
        return self._buffers[key]

    def index_range(self, draw: Draw) -> tuple[int, int]:
        """(first index, index count) of the triangles a draw covers: its file material's part, or all."""
        return self.meshes.index_range(draw)

    # -- textures and samplers -------------------------------------------------
    def texture(self, path: Path, fmt: str) -> Texture:
        key = (path, fmt)
        if key not in self._textures:
            self._textures[key] = create_texture(self.ctx, path, srgb=fmt.endswith("-srgb"),
                                                 mips=self._mipmaps.get(key, True), label=path.name)
        return self._textures[key]

    def sampler(self, spec) -> wgpu.GPUSampler:
        return create_sampler(self.ctx, spec)

