"""GPU resources of a scene's models and materials: meshes, vertex/index buffers, textures, samplers.

Built from the render plan only: a texture is uploaded when the plan lists it (in the format and
with the mip chain it says), a vertex buffer holds exactly the attributes of the variant that
draws it. Everything is cached, so models sharing a mesh file or a texture share the GPU copy.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import wgpu

from wgpurender.core.errors import UserError
from wgpurender.core.mesh import Mesh, index_range, load_mesh
from wgpurender.core.plan import Draw, RenderPlan
from wgpurender.wgpu_path.gpu import GPUContext
from wgpurender.wgpu_path.scene_render.shader_interface import interleave
from wgpurender.wgpu_path.textures import Texture, create_sampler, create_texture


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
        self._meshes: dict[Path, Mesh] = {}
        self._buffers: dict[tuple[Path, tuple[str, ...]], MeshBuffers] = {}
        self._textures: dict[tuple[Path, str], Texture] = {}
        self._needs_tangents = {d.model_path for d in plan.scene_pass.draws
                                if "tangent" in plan.variant(d.variant_key).vertex_attributes}
        self._mipmaps = {(t.path, t.format): t.mipmaps for t in plan.textures}

    # -- meshes ----------------------------------------------------------------
    def mesh(self, path: Path) -> Mesh:
        """The loaded mesh; tangents only when a variant drawing it has a normal map."""
        if path not in self._meshes:
            self._meshes[path] = load_mesh(path, generate_tangents=path in self._needs_tangents,
                                                obj_material=False)  # the scene file gives the material
        return self._meshes[path]

    def mesh_buffers(self, draw: Draw) -> MeshBuffers:
        attributes = self.plan.variant(draw.variant_key).vertex_attributes
        key = (draw.model_path, attributes)
        if key not in self._buffers:
            mesh = self.mesh(draw.model_path)
            _check_mesh(mesh, draw, attributes)
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
        return index_range(self.mesh(draw.model_path), draw)

    # -- textures and samplers -------------------------------------------------
    def texture(self, path: Path, fmt: str) -> Texture:
        key = (path, fmt)
        if key not in self._textures:
            self._textures[key] = create_texture(self.ctx, path, srgb=fmt.endswith("-srgb"),
                                                 mips=self._mipmaps.get(key, True), label=path.name)
        return self._textures[key]

    def sampler(self, spec) -> wgpu.GPUSampler:
        return create_sampler(self.ctx, spec)


def _check_mesh(mesh: Mesh, draw: Draw, attributes: tuple[str, ...]) -> None:
    if "uv" in attributes and not mesh.has_uvs:
        raise UserError(f"{draw.label}: its {draw.material_label} samples textures, but the model file has no "
                        "texture coordinates: export it with UVs, or use a material without maps")
    if "tangent" in attributes and mesh.tangents is None:
        raise UserError(f"{draw.label}: no tangents could be made for its normal map")
