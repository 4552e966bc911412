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
from wgpurender.core.plan.meshes import PlanMeshes
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.textures import Texture, create_sampler, create_texture
from wgpurender.wgpu_path.scene.shader_interface import interleave


@dataclass(frozen=True)
class MeshBuffers:
    """A mesh on the GPU, interleaved for one attribute set."""

    vertex: wgpu.GPUBuffer
    index: wgpu.GPUBuffer
    index_format: str
    index_count: int


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
    def mesh_buffers(self, draw: Draw) -> MeshBuffers:
        attributes = self.plan.variant(draw.variant_key).vertex_attributes
        key = (draw.model_path, attributes)
        if key not in self._buffers:
            mesh = self.meshes.mesh_for(draw)
            dev = self.ctx.device
            self._buffers[key] = MeshBuffers(
                vertex=dev.create_buffer_with_data(data=interleave(mesh, attributes), usage=wgpu.BufferUsage.VERTEX,
                                                   label=f"{draw.label} vertices"),
                index=dev.create_buffer_with_data(data=mesh.index_bytes(), usage=wgpu.BufferUsage.INDEX,
                                                  label=f"{draw.label} indices"),
                index_format=mesh.index_format,
                index_count=mesh.indices.size,
            )
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

