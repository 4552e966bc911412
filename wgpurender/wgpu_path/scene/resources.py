"""GPU resources of a scene's models and materials: meshes, vertex/index buffers, textures, samplers.

Built from the render plan only: a texture is uploaded when the plan lists it (in the format and
with the mip chain it says), a vertex buffer holds exactly the attributes of the variant that
draws it. Everything is cached, so models sharing a mesh file or a texture share the GPU copy.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import wgpu

from wgpurender.core.models.mesh import Mesh
from wgpurender.core.plan import Draw, RenderPlan
from wgpurender.core.plan.meshes import PlanMeshes, buffer_places, changed_rows
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.textures import Texture, create_sampler, create_texture
from wgpurender.wgpu_path.scene.shader_interface import interleave, vertex_stride


class MeshBuffers(NamedTuple):
    """A mesh on the GPU, interleaved for one attribute set: its bytes from ``vertex_offset`` and
    ``index_offset`` of buffers it may share with the scene's other meshes (:meth:`SceneResources.upload_meshes`).
    A named tuple: made once per mesh, 10k times for a scene of 10k mesh files (~4x cheaper than a frozen
    dataclass)."""

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
        self._drawn: dict[tuple, object] = {}  # a re-posed mesh's interleaved rows now on the GPU (playback)
        self.bytes_written = 0  # vertex bytes the playback wrote (rewrite)

    # -- meshes ----------------------------------------------------------------
    def upload_meshes(self, draws) -> list[MeshBuffers]:
        """The meshes of ``draws`` not on the GPU yet, in ONE vertex and ONE index buffer, each mesh's vertices
        starting on a whole vertex of its stride (so a draw names it by ``base_vertex`` with the buffers bound at
        0) and at 4-byte aligned offsets (set_vertex_buffer's and set_index_buffer's rule): a scene of 10k mesh
        files made 20k buffers before, each several wgpu calls (issue 31.3). Where the device's max-buffer-size
        would be passed, the next meshes go into another pair (core/plan/meshes.buffer_places; one mesh too large
        for it is refused in one line). Draw order decides the layout; a draw whose mesh fails its variant's check
        (mesh_for) raises here, as it did when its buffers were made one by one. Returns each draw's buffers, in
        ``draws`` order (its key worked out once, here: the draws' state is made from them)."""
        variant = self.plan.variant
        drawn = [(draw.mesh_key, variant(draw.variant_key).vertex_attributes) for draw in draws]
        pending: dict[tuple, Mesh] = {}
        for draw, key in zip(draws, drawn, strict=True):
            if key not in self._buffers and key not in pending:
                pending[key] = self.meshes.mesh_for(draw)
        if pending:
            self._upload(pending)
        return [self._buffers[key] for key in drawn]

    def _upload(self, pending: dict[tuple, Mesh]) -> None:
        """The ``pending`` meshes ({(mesh key, attributes): mesh}, in draw order) into new buffer pairs."""
        keys, meshes = list(pending), list(pending.values())
        strides = [vertex_stride(key[1]) for key in keys]
        indices = [mesh.index_bytes() for mesh in meshes]
        places = buffer_places([(m.vertex_count * s, len(i)) for m, s, i in zip(meshes, strides, indices, strict=True)],
                               self.ctx.limit("max-buffer-size"), [key[0][0].name for key in keys], strides)
        dev = self.ctx.device
        made = {}  # named as the plan lists them (RenderPlan.buffers)
        usage = wgpu.BufferUsage
        for pair, (vertex, index) in _pair_bytes(keys, meshes, places, indices).items():
            made[pair] = (dev.create_buffer_with_data(data=vertex, usage=usage.VERTEX | usage.COPY_DST,
                                                     label="scene-vertices"),
                          dev.create_buffer_with_data(data=index, usage=usage.INDEX | usage.COPY_DST,
                                                      label="scene-indices"))
        for key, mesh, (pair, v_at, i_at), stride in zip(keys, meshes, places, strides, strict=True):
            self._buffers[key] = MeshBuffers(*made[pair], mesh.index_format, mesh.indices.size, v_at, i_at,
                                             v_at // stride, i_at // mesh.indices.itemsize)

    def mesh_buffers(self, draw: Draw) -> MeshBuffers:
        """The draw's mesh on the GPU (uploaded now, alone, unless :meth:`upload_meshes` did already)."""
        key = (draw.mesh_key, self.plan.variant(draw.variant_key).vertex_attributes)
        return self._buffers[key] if key in self._buffers else self.upload_meshes([draw])[0]

    def index_range(self, draw: Draw) -> tuple[int, int]:
        """(first index, index count) of the triangles a draw covers: its file material's part, or all."""
        return self.meshes.index_range(draw)

    def rewrite(self, mesh_key: tuple, mesh: Mesh) -> int:
        """Write ``mesh`` (re-posed: same vertices and triangles, moved) over the GPU copies of ``mesh_key``, in
        place: within its own vertex range of the shared buffer, only the rows from the first to the last vertex
        that moved (core/plan/meshes.changed_rows), and its indices only where a mirroring node turned the winding;
        the window's playback. The number of buffer writes (``bytes_written`` counts their bytes)."""
        before = self.meshes.mesh(mesh_key)
        writes, turned = 0, self.meshes.turned(mesh_key, mesh)
        for (key, attributes), buffers in self._buffers.items():
            if key != mesh_key:
                continue
            rows = interleave([mesh], attributes)
            drawn = self._drawn.get((key, attributes))
            first, end = changed_rows(drawn if drawn is not None else interleave([before], attributes), rows)
            self._drawn[(key, attributes)] = rows
            if first < end:
                data = rows[first:end].tobytes()
                self.ctx.queue.write_buffer(buffers.vertex, buffers.vertex_offset + first * rows.strides[0], data)
                writes, self.bytes_written = writes + 1, self.bytes_written + len(data)
            if turned:
                self.ctx.queue.write_buffer(buffers.index, buffers.index_offset, mesh.index_bytes())
                writes += 1
        return writes

    # -- textures and samplers -------------------------------------------------
    def texture(self, path: Path, fmt: str) -> Texture:
        key = (path, fmt)
        if key not in self._textures:
            self._textures[key] = create_texture(self.ctx, path, srgb=fmt.endswith("-srgb"),
                                                 mips=self._mipmaps.get(key, True), label=path.name)
        return self._textures[key]

    def sampler(self, spec) -> wgpu.GPUSampler:
        return create_sampler(self.ctx, spec)


def _pair_bytes(keys: list[tuple], meshes: list[Mesh], places: list[tuple[int, int, int]],
                indices: list[bytes]) -> dict[int, tuple[bytes, bytes]]:
    """Each buffer pair's (vertex bytes, index bytes): each mesh at its place (zeros up to it). Consecutive
    meshes of one pair and one attribute set lie end to end (buffer_places starts a mesh on a whole vertex of its
    stride, where the one before ends) and are interleaved together (one run; 10k cube files are one)."""
    vertex: dict[int, list[bytes]] = {}
    index: dict[int, list[bytes]] = {}
    ends: dict[int, int] = {}
    k = 0
    while k < len(meshes):
        pair, start, _ = places[k]
        run = k + 1
        # one pair and one attribute set (so one stride): buffer_places put them end to end
        while run < len(meshes) and places[run][0] == pair and keys[run][1] == keys[k][1]:
            run += 1
        data = interleave(meshes[k:run], keys[k][1]).tobytes()
        pieces = vertex.setdefault(pair, [])
        pieces += [b"\0" * (start - ends.get(pair, 0)), data]  # up to its place: a whole vertex of its stride
        ends[pair] = start + len(data)
        index.setdefault(pair, []).extend(indices[k:run])  # index_bytes is already a multiple of 4
        k = run
    # float32 strides keep a vertex buffer whole; the buffer's size rule, stated
    return {pair: (b"".join(vertex[pair]) + b"\0" * (-ends[pair] % 4), b"".join(index[pair])) for pair in vertex}
