"""The scene's frozen dataclasses and the value sets they accept (what a validated scene file becomes)."""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from wgpurender.core.course.formats import OUTPUT_FORMATS  # noqa: F401  (the value sets a scene accepts: one home each)
from wgpurender.core.course.samplers import ADDRESS_MODES, FILTERS, MAX_ANISOTROPY  # noqa: F401
from wgpurender.core.course.shading import DEFAULT_ALBEDO_COLOR, DEFAULT_CLEAR_COLOR, DEFAULT_ROUGHNESS
from wgpurender.core.files.input_files import file_suffix
from wgpurender.core.models.gltf_animation import Pose
from wgpurender.core.view import transforms

MAX_LIGHTS = 8
CONVENTIONS = ("wgpu", "glm-vulkan")
LIGHT_TYPES = ("directional", "point")

Vec3 = tuple[float, float, float]
Vec4 = tuple[float, float, float, float]


@dataclass(frozen=True)
class Camera:
    """A look-at camera with a perspective projection.

    ``convention = "glm-vulkan"``: the scene was set up for the Vulkan tutorial,
    whose projection is GLM's (right-handed, depth 0..1) with ``proj[1][1] *= -1``
    because Vulkan's NDC y points down. wgpu's NDC y points up (it flips to
    framebuffer rows itself), so drawn on wgpu that matrix gives an upside-down
    image, and the flip also turns every triangle's winding around, which is why
    the tutorial switches front_face to counter-clockwise. :meth:`source_projection`
    is the matrix as the convention writes it (what the raw-Vulkan reference path
    uploads); :meth:`projection` is what wgpu must use: ``clip_correction @
    source_projection``, which undoes the flip, so winding and orientation are the
    mesh's own again (counter-clockwise front faces).

    A model file's camera (``[camera] from_model``, core/scene/gltf_cameras.py) fills the same fields from its node
    and numbers, and may add what a scene's own camera never has: ``far = inf`` (a perspective camera without
    zfar), the file's ``aspect_ratio`` (None: the target's), an ``orthographic`` projection of half-extents
    ``xmag`` and ``ymag``, ``origin`` (which file camera it is, for ``--explain``) and ``file_camera`` ((model
    index, camera index): placed again when ``--time`` poses the model).
    """

    eye: Vec3
    target: Vec3
    up: Vec3 = (0.0, 1.0, 0.0)
    fov_y: float = 45.0
    near: float = 0.1
    far: float = 100.0
    convention: str = "wgpu"
    projection_type: str = "perspective"  # or "orthographic" (a model file's camera only)
    xmag: float = 1.0
    ymag: float = 1.0
    aspect_ratio: float | None = None
    origin: str = ""
    file_camera: tuple[int, int] | None = None

    def view(self) -> np.ndarray:
        return transforms.look_at(self.eye, self.target, self.up)

    def eye_vector(self) -> tuple[float, float, float, float]:
        """The Camera uniform's ``eye``: the position with w = 1, or for an orthographic camera the direction
        towards it with w = 0, so the shaders' view vector ``eye.xyz - position * eye.w`` is parallel there."""
        if self.projection_type == "orthographic":
            back = np.asarray(self.eye, np.float64) - np.asarray(self.target, np.float64)
            return (*(float(v) for v in back / np.linalg.norm(back)), 0.0)
        return (*(float(v) for v in self.eye), 1.0)

    def source_projection(self, aspect: float) -> np.ndarray:
        if self.projection_type == "orthographic":
            return transforms.orthographic(self.xmag, self.ymag, self.near, self.far)
        aspect = self.aspect_ratio if self.aspect_ratio is not None else aspect
        proj = transforms.perspective(self.fov_y, aspect, self.near, self.far)
        if self.convention == "glm-vulkan":
            proj[1, 1] *= -1.0
        return proj

    @property
    def clip_correction(self) -> np.ndarray:
        """diag(1, -1, 1, 1) for glm-vulkan (undoes the Y flip), identity otherwise."""
        return np.diag([1.0, -1.0 if self.convention == "glm-vulkan" else 1.0, 1.0, 1.0])

    def projection(self, aspect: float) -> np.ndarray:
        return self.clip_correction @ self.source_projection(aspect)


@dataclass(frozen=True)
class SamplerSettings:
    """How a material's textures are sampled. ``mipmaps`` also decides whether a mip chain is built.

    ``mipmaps = false`` with ``anisotropy > 1`` is the Vulkan tutorial's chapter-28 sampler: one mip level
    (maxLod 0) sampled anisotropically; the mipmap filter stays linear there because wgpu allows anisotropy
    only with linear min, mag and mipmap filters (with one level it changes nothing).
    """

    filter: str = "linear"
    mipmaps: bool = True
    anisotropy: int = 1
    address_mode: str = "repeat"

    def spec(self):
        """The :class:`wgpurender.core.course.samplers.SamplerSpec` for these settings."""
        from wgpurender.core.course.samplers import SamplerSpec

        return SamplerSpec(
            mag_filter=self.filter,
            min_filter=self.filter,
            mipmap_filter=self.filter if (self.mipmaps or self.anisotropy > 1) else "nearest",
            address_mode_u=self.address_mode,
            address_mode_v=self.address_mode,
            address_mode_w=self.address_mode,
            max_anisotropy=self.anisotropy,
            lod_max_clamp=32.0 if self.mipmaps else 0.0,
        )


@dataclass(frozen=True)
class Material:
    """A surface. ``written`` keeps each key's value as the file wrote it (for the plan's explanations);
    ``origin`` says where it was defined, e.g. ``[materials.brick]`` or ``models[0].material (inline)``."""

    name: str
    albedo_color: Vec4 = DEFAULT_ALBEDO_COLOR
    albedo_map: Path | None = None
    normal_map: Path | None = None
    roughness_map: Path | None = None
    roughness: float = DEFAULT_ROUGHNESS
    unlit: bool = False
    uv_flip_v: bool = False
    sampler: SamplerSettings = field(default_factory=SamplerSettings)
    origin: str = "default"
    written: tuple[tuple[str, str], ...] = ()
    # What a model file's own material can say beyond the scene keys (core/scene/gltf_materials.py makes these):
    vertex_colors: bool = False  # multiply the base colour by the vertex colour (glTF COLOR_0)
    double_sided: bool = False  # no back-face culling; back faces are lit with the normal turned around
    alpha_mode: str = "opaque"  # "opaque", "mask" (discard below alpha_cutoff) or "blend" (unsorted, see docs)
    alpha_cutoff: float = 0.5
    normal_strength: float | None = None  # None: course.shading.NORMAL_STRENGTH (glTF normalTexture.scale)
    roughness_map_scale: float = 1.0  # multiplies a roughness map's G (glTF roughnessFactor)
    texture_samplers: tuple[tuple[str, object], ...] = ()  # (feature, SamplerSpec): a sampler per texture
    texture_mipmaps: tuple[tuple[str, bool], ...] = ()  # (feature, builds a mip chain) when per texture
    part: int | None = None  # the model file's material index this stands for (None: the whole model)
    topology: str = "triangle-list"  # glTF points ("point-list") and lines ("line-list") draw with their own
    emissive_color: Vec3 = (0.0, 0.0, 0.0)  # linear radiance added to the shaded colour (glTF emissiveFactor)
    emissive_map: Path | None = None  # sRGB, multiplies emissive_color (glTF emissiveTexture)
    occlusion_map: Path | None = None  # linear, R channel scales the ambient term (glTF occlusionTexture)
    occlusion_strength: float = 1.0
    # The material model (core/plan/shading_models.py): "blinn-phong" (the course's) or "pbr" (glTF
    # metallic-roughness, shaders_wgsl/pbr.wgsl), with the metallic factor (times the roughness map's B channel).
    shading_model: str = "blinn-phong"
    metallic: float = 0.0
    # (feature, slot k >= 1, what it samples): the textures that sample the mesh's coordinate slot k (a glTF texCoord
    # or KHR_texture_transform of their own: core/models/gltf_geometry.uv_slots); the others sample slot 0.
    uv_slots: tuple[tuple[str, int, str], ...] = ()
    # KHR_materials_clearcoat (a glTF metallic-roughness material only; shaders_wgsl/clearcoat.wgsl): a GGX layer of
    # ior 1.5 over the material, weight clearcoat (x the clearcoat map's R), roughness clearcoat_roughness (x the
    # clearcoat roughness map's G), its own normal (the geometric one, or the clearcoat normal map's with its scale)
    clearcoat: float = 0.0
    clearcoat_roughness: float = 0.0
    clearcoat_map: Path | None = None
    clearcoat_roughness_map: Path | None = None
    clearcoat_normal_map: Path | None = None
    clearcoat_normal_scale: float = 1.0

    @property
    def textures(self) -> dict[str, Path]:
        maps = {"albedo_map": self.albedo_map, "normal_map": self.normal_map, "roughness_map": self.roughness_map,
                "emissive_map": self.emissive_map, "occlusion_map": self.occlusion_map,
                "clearcoat_map": self.clearcoat_map, "clearcoat_roughness_map": self.clearcoat_roughness_map,
                "clearcoat_normal_map": self.clearcoat_normal_map}
        return {k: v for k, v in maps.items() if v is not None}

    def as_written(self, key: str) -> str:
        return dict(self.written).get(key, "")


DEFAULT_MATERIAL = Material(name="default", origin="default (no material given)")


@dataclass(frozen=True)
class Transform:
    """The model's world matrix (row-major, acting on column vectors) and how it was written."""

    matrix: tuple[tuple[float, ...], ...]
    description: str = "identity"

    def array(self) -> np.ndarray:
        return np.array(self.matrix, dtype=np.float64)

    @property
    def mirrors(self) -> bool:
        """Whether the matrix mirrors (its 3x3 part's determinant is negative: the winding turns around)."""
        (a, b, c), (d, e, f), (g, h, i) = (row[:3] for row in self.matrix[:3])
        return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g) < 0


def _rows(m: np.ndarray) -> tuple[tuple[float, ...], ...]:
    return tuple(map(tuple, np.asarray(m, dtype=np.float64).tolist()))  # Python floats, as float() gives


IDENTITY = Transform(_rows(np.eye(4)))

MAX_INSTANCES = 4_000_000  # copies of one model: 64 bytes each here, 128 on the GPU (bounded memory)


@dataclass(frozen=True)
class Placements:
    """N copies of one model, compactly: each copy's matrix, relative to the model's ``transform``.

    Copy i is drawn with world matrix ``model.transform @ matrix(i)``: the model's transform is the parent of
    its copies, as a glTF node is the parent of EXT_mesh_gpu_instancing's per-instance TRS. Made from a scene's
    ``instances`` block (core/scene/instances.py) or a glTF file's instancing extension; the plan batches
    them into one instanced draw. ``data`` is float32 (N, 4, 4) row-major (acting on column vectors): bytes, so
    the frozen scene stays comparable and hashable."""

    data: bytes
    count: int
    description: str

    @classmethod
    def of(cls, matrices: np.ndarray, description: str) -> Placements:
        m = np.ascontiguousarray(matrices, dtype=np.float32).reshape(-1, 4, 4)
        return cls(m.tobytes(), int(m.shape[0]), description)

    def array(self) -> np.ndarray:
        """(count, 4, 4) float32, read-only (a view of ``data``)."""
        return np.frombuffer(self.data, dtype=np.float32).reshape(self.count, 4, 4)


@dataclass(frozen=True)
class ModelMaterials:
    """The materials a model draws with from its file (one per file material its triangles use, in file order;
    ``part`` is the file's material index, -1 for primitives without one) and what was taken and ignored, for
    ``--explain``. Read once when the scene loads (core/scene/file_materials.py)."""

    materials: tuple[Material, ...]
    taken: tuple[str, ...]
    ignored: tuple[str, ...]


@dataclass(frozen=True)
class Model:
    index: int
    path: Path  # resolved
    written_path: str  # as in the file
    material: Material
    transform: Transform = IDENTITY
    # True when the scene names no material: a glTF model then draws with its own materials (core/scene/gltf_materials)
    material_from_file: bool = False
    # those materials, read once when the scene loads (core/scene/file_materials.py); None: the scene's material
    file_materials: ModelMaterials | None = None
    placements: Placements | None = None  # None: one copy, at ``transform``
    pose: Pose | None = None  # a glTF file's animation at a time (core/models/gltf_animation.py); None: at rest
    motion: tuple[str, ...] = ()  # --explain lines: the animation sampled and the skins posed (core/scene/model_motion)

    @property
    def label(self) -> str:
        return f"models[{self.index}] '{self.written_path}'"

    @functools.cached_property
    def suffix(self) -> str:
        """Its file's format as its resolved path's suffix, lower case (".obj", ".glb"): worked out once per
        model, where the scene checks, the file data, the plan and the meshes each ask (issue 31.3)."""
        return file_suffix(os.fspath(self.path)).lower()

    @property
    def instance_count(self) -> int:
        return 1 if self.placements is None else self.placements.count

    def worlds(self) -> np.ndarray:
        """(N, 4, 4) float64: every copy's world matrix (``transform @ placement``), or the transform alone."""
        parent = self.transform.array()
        if self.placements is None:
            return parent[None]
        return parent @ self.placements.array().astype(np.float64)


@dataclass(frozen=True)
class Light:
    """``direction`` (directional: the way the light travels) or ``position`` (point), linear colour.

    A point light may also have a ``range`` (> 0: the KHR_lights_punctual window, E x clamp(1 - (d / range)^4, 0,
    1)) and a spot ``cone`` (inner, outer half-angles in radians, around ``direction``, the way the spot points:
    E x clamp((cos a - cos outer) / (cos inner - cos outer), 0, 1)^2, a the angle off the axis); the model
    file's KHR_lights_punctual lights come with these (core/scene/gltf_lights.py), ``origin`` saying where."""

    index: int
    type: str
    color: Vec3 = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    direction: Vec3 | None = None
    position: Vec3 | None = None
    range: float = 0.0
    cone: tuple[float, float] | None = None
    origin: str = ""

    @property
    def label(self) -> str:
        return self.origin or f"lights[{self.index}]"

    def shape(self) -> tuple[tuple[float, float, float], float, float, float]:
        """A point light's window as the shaders take it: (spot axis, cone scale, cone offset, range), with
        cone factor clamp(dot(axis, -l) * scale + offset, 0, 1)^2 (scale 0, offset 1: no cone) and range 0 for
        none (the plain inverse square)."""
        if self.cone is None:
            return (0.0, 0.0, -1.0), 0.0, 1.0, self.range
        inner, outer = np.cos(self.cone[0]), np.cos(self.cone[1])
        scale = 1.0 / max(1e-3, inner - outer)
        axis = np.asarray(self.direction, np.float64) / np.linalg.norm(self.direction)
        return tuple(float(a) for a in axis), float(scale), float(-outer * scale), self.range


@dataclass(frozen=True)
class RenderSettings:
    size: tuple[int, int] = (800, 600)
    msaa: int = 4
    hdr: bool = True
    clear_color: Vec4 = DEFAULT_CLEAR_COLOR
    output_format: str = "rgba8unorm-srgb"
    post_fuse: bool = True  # fuse consecutive per-pixel effects into one pass (false: one pass each, for teaching)
    post_path: str = "auto"  # post passes as fragment or compute shaders; auto: chosen per adapter (core/plan/)


@dataclass(frozen=True)
class PostStep:
    """One [[post]] entry: an effect name and its validated parameters (defaults filled in)."""

    index: int
    effect: str
    params: tuple[tuple[str, float | str], ...] = ()
    written: tuple[str, ...] = ()  # the parameter names the file set

    def step(self):
        """The GPU-free :class:`wgpurender.core.course.effects.EffectStep` the plan lists (asked for by this entry)."""
        from wgpurender.core.course.effects import EffectStep

        return EffectStep(self.effect, self.params, f'[[post]] #{self.index} effect = "{self.effect}"')


@dataclass(frozen=True)
class Scene:
    path: Path
    camera: Camera
    models: tuple[Model, ...] = ()
    materials: dict[str, Material] = field(default_factory=dict)
    lights: tuple[Light, ...] = ()
    render: RenderSettings = field(default_factory=RenderSettings)
    post: tuple[PostStep, ...] = ()
    description: str = ""
    environment: Any = None  # core/scene/environment_block.Environment: image-based lighting, or None

    @property
    def folder(self) -> Path:
        return self.path.parent
