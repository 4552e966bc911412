"""The scene's models and materials on the raw path: vertex/index buffers, textures, samplers.

Meshes come from :func:`wgpurender.core.models.mesh.load_mesh` (the same loader as the wgpu path: both paths
must draw the same triangles), interleaved with exactly the attributes of the variant that draws
them and uploaded through staging buffers (memory.upload_buffer: vkCmdCopyBuffer into
DEVICE_LOCAL memory). Textures go through raw_path/device/textures.py (staging upload, mip chain drawn
level by level with the wgpu path's box filter), samplers are VkSamplers made from the plan's
SamplerSpec. Everything is cached, so models sharing a file or a texture share the copy.
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import vulkan as vk

from wgpurender.core.models.mesh import Mesh
from wgpurender.core.plan import Draw, RenderPlan
from wgpurender.core.plan.meshes import PlanMeshes, changed_rows
from wgpurender.core.plan.model import EXTRA_UV_SLOTS
from wgpurender.core.scene.texture_pixels import load_image
from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.memory import (
    HOST_MEMORY,
    Buffer,
    create_buffer,
    record_copy,
    upload_buffer,
    write_host_buffer,
)
from wgpurender.raw_path.device.textures import TextureImage, create_sampler, upload_texture

# attribute -> (shader location, float count): the locations of shaders_glsl/scene.vert
ATTRIBUTES = {"position": (0, 3), "normal": (1, 3), "uv": (2, 2), "tangent": (3, 4), "color": (4, 4),
              **{f"uv{k}": (4 + k, 2) for k in range(1, EXTRA_UV_SLOTS + 1)}}  # coordinate slots 1..4
INDEX_TYPES = {np.dtype(np.uint16): vk.VK_INDEX_TYPE_UINT16, np.dtype(np.uint32): vk.VK_INDEX_TYPE_UINT32}


@dataclass(frozen=True)
class MeshBuffers:
    vertex: Buffer
    index: Buffer
    index_type: int
    index_count: int


def vertex_input(attributes: tuple[str, ...]) -> tuple[list, list]:
    """One interleaved binding holding ``attributes`` in order: its binding and attribute descriptions."""
    descriptions, offset = [], 0
    for name in attributes:
        location, n = ATTRIBUTES[name]
        fmt = {2: vk.VK_FORMAT_R32G32_SFLOAT, 3: vk.VK_FORMAT_R32G32B32_SFLOAT, 4: vk.VK_FORMAT_R32G32B32A32_SFLOAT}[n]
        descriptions.append(vk.VkVertexInputAttributeDescription(location=location, binding=0, format=fmt,
                                                                 offset=offset))
        offset += 4 * n
    binding = vk.VkVertexInputBindingDescription(binding=0, stride=offset, inputRate=vk.VK_VERTEX_INPUT_RATE_VERTEX)
    return [binding], descriptions


def interleave(mesh: Mesh, attributes: tuple[str, ...]) -> np.ndarray:
    return np.ascontiguousarray(np.concatenate([mesh.attribute(a) for a in attributes], axis=1), dtype=np.float32)


class SceneResources:
    """Buffers, textures and samplers of one plan, destroyed with ``owned``."""

    def __init__(self, ctx: VulkanContext, owned: ExitStack, plan: RenderPlan) -> None:
        self.ctx, self.owned, self.plan = ctx, owned, plan
        self.meshes = PlanMeshes(plan)  # what is loaded and checked: the core's, as on the wgpu path
        self._buffers: dict[tuple[Path, tuple[str, ...]], MeshBuffers] = {}
        self._textures: dict[tuple[Path, bool], TextureImage] = {}
        self._samplers: dict[object, object] = {}
        self._staging: dict[object, object] = {}  # a rewritten buffer's host staging buffer (playback)
        self._drawn: dict[tuple, np.ndarray] = {}  # a re-posed mesh's interleaved rows now on the GPU (playback)
        self.bytes_copied = 0  # vertex bytes the playback copied (rewrite)
        self._mipmaps = {(t.path, t.format.endswith("-srgb")): t.mipmaps for t in plan.textures}

    def mesh_buffers(self, draw: Draw) -> MeshBuffers:
        attributes = self.plan.variant(draw.variant_key).vertex_attributes
        key = (draw.mesh_key, attributes)
        if key not in self._buffers:
            mesh = self.meshes.mesh_for(draw)
            vertex_stage = vk.VK_PIPELINE_STAGE_VERTEX_INPUT_BIT
            vertex = upload_buffer(self.ctx, self.owned, interleave(mesh, attributes),
                                   vk.VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vertex_stage,
                                   vk.VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT)
            indices = mesh.all_indices()  # the triangles', then any glTF points' and lines'
            index = upload_buffer(self.ctx, self.owned, indices, vk.VK_BUFFER_USAGE_INDEX_BUFFER_BIT, vertex_stage,
                                  vk.VK_ACCESS_INDEX_READ_BIT)
            self._buffers[key] = MeshBuffers(vertex, index, INDEX_TYPES[indices.dtype], indices.size)
        return self._buffers[key]

    def index_range(self, draw: Draw) -> tuple[int, int]:
        """(first index, index count) of the triangles a draw covers: its file material's part, or all."""
        return self.meshes.index_range(draw)

    def rewrite(self, cmd, mesh_key: tuple, mesh: Mesh) -> int:
        """Record into ``cmd`` the copy of ``mesh`` (re-posed: same vertices and triangles, moved) over the buffers
        of ``mesh_key``: only the rows from the first to the last vertex that moved (core/plan/meshes.changed_rows),
        and its indices only where a mirroring node turned the winding, each through its own host staging buffer
        (made once, written while the frame's fence says the last copy is done); the window's playback. The number
        of buffer copies (``bytes_copied`` counts their vertex bytes)."""
        before = self.meshes.mesh(mesh_key)
        writes, turned = 0, self.meshes.turned(mesh_key, mesh)
        for (key, attributes), buffers in self._buffers.items():
            if key != mesh_key:
                continue
            rows = interleave(mesh, attributes)
            drawn = self._drawn.get((key, attributes))
            first, end = changed_rows(drawn if drawn is not None else interleave(before, attributes), rows)
            self._drawn[(key, attributes)] = rows
            if first < end:
                stride = rows.strides[0]
                self._copy(cmd, buffers.vertex, rows, vk.VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT, first * stride,
                           (end - first) * stride)
                writes, self.bytes_copied = writes + 1, self.bytes_copied + (end - first) * stride
            if turned:
                indices = mesh.all_indices()
                self._copy(cmd, buffers.index, indices, vk.VK_ACCESS_INDEX_READ_BIT, 0, indices.nbytes)
                writes += 1
        return writes

    def _copy(self, cmd, target, data: np.ndarray, reader_access: int, offset: int, size: int) -> None:
        if target.handle not in self._staging:
            self._staging[target.handle] = create_buffer(self.ctx, self.owned, target.size,
                                                         vk.VK_BUFFER_USAGE_TRANSFER_SRC_BIT, HOST_MEMORY)
        staging = self._staging[target.handle]
        write_host_buffer(self.ctx, staging, data)
        # the frame's earlier reads of the buffer (the last frame of this slot) are done: its fence was waited on
        record_copy(cmd, staging, target, size, vk.VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, reader_access, offset)

    def texture(self, path: Path, srgb: bool) -> TextureImage:
        """Albedo maps as R8G8B8A8_SRGB (decoded on sampling), data maps as R8G8B8A8_UNORM, as the plan lists."""
        key = (path, srgb)
        if key not in self._textures:
            pixels = load_image(path, max_dim=self.ctx.limits.max_image_dimension_2d)
            self._textures[key] = upload_texture(self.ctx, self.owned, pixels, srgb, self._mipmaps.get(key, True))
        return self._textures[key]

    def sampler(self, spec):
        if spec not in self._samplers:
            self._samplers[spec] = create_sampler(self.ctx, self.owned, spec)
        return self._samplers[spec]

