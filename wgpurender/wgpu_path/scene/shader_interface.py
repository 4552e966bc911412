"""What the scene shader and Python agree on: uniform structs, vertex layouts, and the specialised WGSL.

Every struct is declared once here with :mod:`wgpurender.core.shaders.uniforms`; the WGSL declarations
are generated into shaders_wgsl/scene.wgsl's ``{{STRUCTS}}``. Lit and unlit variants see
different declarations of the same buffers: the unlit ``Camera`` is only the first fields
of the lit one (proj, view, eye), the unlit ``Object`` only ``world`` (then padding: it is the
element of a storage array, whose stride is its size, 128 bytes in every variant), the unlit
``Material`` only the base colour. Offsets of the shared prefix are identical (asserted
below), so one camera buffer and one object buffer serve every variant of a scene, and
the unlit shader contains no light struct, no normal matrix and no lighting code.

Bindings (the course's descriptor sets):
  group 0 Camera   - written once per frame (non-dynamic)
  group 1 Object   - every instance's data in ONE storage buffer, read at instance_index (batches.py); with the
                     plan's instance_data "vertex" there is no group 1: the same blocks are a vertex buffer
                     stepped per instance (instance_layout) and the material is group 1
  group 2 material - binding 0: Material (only without immediates), 2: albedo, 3: normal map,
                     4: roughness map, each with its own sampler (1, 5, 6), only those the variant samples;
                     7/8 emissive, 9/10 occlusion, 12/13, 14/15, 16/17 the clearcoat maps (texture/sampler);
                     11: the image-based lighting maps (storage buffer, ibl variants)
  immediates       - Material (per-draw factors) when the adapter has "immediates"
"""

from __future__ import annotations

import functools

import numpy as np

from wgpurender.core.models.mesh import Mesh
from wgpurender.core.plan import ShaderVariant
from wgpurender.core.plan.model import EXTRA_UV_SLOTS, UV_SLOT_FLAGS
from wgpurender.core.scene import MAX_LIGHTS
from wgpurender.core.shaders.shader_variants import specialise
from wgpurender.core.shaders.uniforms import F32, MAT3, MAT4, VEC4F, VEC4U, Array, Struct, wgsl_structs
from wgpurender.wgpu_path.device.shaders import load_wgsl

SHADER = "scene.wgsl"
PBR_FUNCTIONS = "pbr.wgsl"  # the glTF metallic-roughness BRDF, inserted for variants with the "pbr" flag
IBL_FUNCTIONS = "ibl_shading.wgsl"  # image-based lighting, inserted for variants with the "ibl" flag
CLEARCOAT_FUNCTIONS = "clearcoat.wgsl"  # KHR_materials_clearcoat's layer, for variants with the "clearcoat" flag
IBL_BINDING = 11  # group 2: the image-based lighting maps (a read-only storage buffer)

_CAMERA_VIEW = [("proj", MAT4), ("view", MAT4), ("eye", VEC4F)]
DIRECTIONAL_LIGHT = Struct("DirectionalLight", [("direction", VEC4F), ("radiance", VEC4F)])
# position.w: range (0: none); radiance.w: spot cone offset; spot: the spot's axis and cone scale (Light.shape)
POINT_LIGHT = Struct("PointLight", [("position", VEC4F), ("radiance", VEC4F), ("spot", VEC4F)])
CAMERA_UNLIT = Struct("Camera", _CAMERA_VIEW)
CAMERA = Struct("Camera", _CAMERA_VIEW + [
    ("ambient", VEC4F),  # rgb: ambient radiance multiplied by albedo (see scene.wgsl)
    ("light_counts", VEC4U),  # x: directional, y: point (the loops use the variant's compile-time counts)
    ("directional", Array(DIRECTIONAL_LIGHT, MAX_LIGHTS)),
    ("point", Array(POINT_LIGHT, MAX_LIGHTS)),
])
# Unlit: only world is read; the rest is padding, so the storage array's stride (the struct's size) stays 128
OBJECT_UNLIT = Struct("Object", [("world", MAT4), ("unused", Array(VEC4F, 4))])
OBJECT = Struct("Object", [("world", MAT4), ("normal", MAT3), ("mirror", F32)])  # mirror: sign of det(world)
_MATERIAL_UNLIT_FIELDS = [("base_color", VEC4F)]
_MATERIAL_FIELDS = _MATERIAL_UNLIT_FIELDS + [("roughness", F32), ("normal_strength", F32), ("specular", F32)]
# The glTF metallic-roughness variant ("pbr") has no use for Blinn-Phong's specular reflectance: its metallic factor
# takes that slot, so a PBR material's block is no larger than a Blinn-Phong one.
_MATERIAL_PBR_FIELDS = _MATERIAL_UNLIT_FIELDS + [("roughness", F32), ("normal_strength", F32), ("metallic", F32)]
MATERIAL_UNLIT = Struct("Material", _MATERIAL_UNLIT_FIELDS)
MATERIAL = Struct("Material", _MATERIAL_FIELDS)
MATERIAL_PBR = Struct("Material", _MATERIAL_PBR_FIELDS)

# Model-file materials append, when their variant has the feature, in core/course/shading.material_factors' order:
_MATERIAL_EXTRAS = (("alpha_mask", "alpha_cutoff", F32), ("occlusion_map", "occlusion_strength", F32),
                    ("clearcoat", "clearcoat", F32), ("clearcoat", "clearcoat_roughness", F32),
                    ("clearcoat", "clearcoat_normal_scale", F32), ("emissive", "emissive", VEC4F))

for _small, _full in ((CAMERA_UNLIT, CAMERA), (OBJECT_UNLIT, OBJECT), (MATERIAL_UNLIT, MATERIAL)):
    assert all(_full.offsets[name] == offset for name, offset in _small.offsets.items() if name != "unused"), _small
assert OBJECT_UNLIT.size == OBJECT.size == 128

# Vertex attributes: location and float count (position always; the plan decides the others).
ATTRIBUTE_LOCATIONS = {"position": (0, 3), "normal": (1, 3), "uv": (2, 2), "tangent": (3, 4), "color": (4, 4),
                       **{f"uv{k}": (4 + k, 2) for k in range(1, EXTRA_UV_SLOTS + 1)}}  # coordinate slots 1..4
TEXTURE_BINDINGS = {"albedo_map": 2, "normal_map": 3, "roughness_map": 4, "emissive_map": 7, "occlusion_map": 9,
                    "clearcoat_map": 12, "clearcoat_roughness_map": 14, "clearcoat_normal_map": 16}
SAMPLER_BINDINGS = {"albedo_map": 1, "normal_map": 5, "roughness_map": 6, "emissive_map": 8,
                    "occlusion_map": 10, "clearcoat_map": 13, "clearcoat_roughness_map": 15,
                    "clearcoat_normal_map": 17}  # each texture's own sampler
# At most 8 textures and 8 samplers in the fragment stage: half of WebGPU's default limits (16 each)
MATERIAL_BINDING = 0


def is_lit(variant: ShaderVariant) -> bool:
    return "lighting" in variant.flags


def samples_textures(variant: ShaderVariant) -> bool:
    return any(f in variant.flags for f in TEXTURE_BINDINGS)


def camera_struct(variant: ShaderVariant) -> Struct:
    return CAMERA if is_lit(variant) else CAMERA_UNLIT


def object_struct(variant: ShaderVariant) -> Struct:
    return OBJECT if is_lit(variant) else OBJECT_UNLIT


def material_struct(variant: ShaderVariant) -> Struct:
    extras = tuple((name, kind) for flag, name, kind in _MATERIAL_EXTRAS if flag in variant.flags)
    pbr = "pbr" in variant.flags
    if not extras:
        return (MATERIAL_PBR if pbr else MATERIAL) if is_lit(variant) else MATERIAL_UNLIT
    return _extended_material(is_lit(variant), pbr, extras)


@functools.cache
def _extended_material(lit: bool, pbr: bool, extras: tuple) -> Struct:
    fields = (_MATERIAL_PBR_FIELDS if pbr else _MATERIAL_FIELDS) if lit else _MATERIAL_UNLIT_FIELDS
    return Struct("Material", fields + list(extras))


def vertex_layout(variant: ShaderVariant) -> dict:
    """One interleaved buffer holding exactly the variant's attributes, in ATTRIBUTE_LOCATIONS order."""
    attributes, offset = [], 0
    for name in variant.vertex_attributes:
        location, n = ATTRIBUTE_LOCATIONS[name]
        attributes.append({"shader_location": location, "format": f"float32x{n}", "offset": offset})
        offset += 4 * n
    return {"array_stride": offset, "step_mode": "vertex", "attributes": attributes}


def interleave(meshes: Mesh | list[Mesh], attributes: tuple[str, ...]) -> np.ndarray:
    """(N, floats) float32 vertex data with the given attributes, for :func:`vertex_layout`; of a list of meshes,
    their vertices one after another, made with one concatenation per attribute rather than one interleave per
    mesh (a scene of 10k mesh files: issue 31.3)."""
    meshes = [meshes] if isinstance(meshes, Mesh) else meshes
    columns = [np.concatenate([m.attribute(a) for m in meshes]) for a in attributes]
    return np.ascontiguousarray(np.concatenate(columns, axis=1), dtype=np.float32)


@functools.cache  # asked once per mesh of a scene: 10k times for a handful of attribute sets
def vertex_stride(attributes: tuple[str, ...]) -> int:
    """Bytes per vertex of :func:`interleave`'s data (float32 attributes)."""
    return sum(4 * ATTRIBUTE_LOCATIONS[name][1] for name in attributes)


def shader_features(variant: ShaderVariant, immediates: bool, culled: bool = False,
                    instance_data: str = "storage") -> set[str]:
    """The variant's flags plus the derived ones the template tests (uv, light kinds, immediates, culled,
    instance_attributes)."""
    features = set(variant.flags) | ({"culled"} if culled else set())
    if instance_data == "vertex":
        features.add("instance_attributes")
    if samples_textures(variant):
        features.add("uv")
    if "tangent" in variant.vertex_attributes:
        features.add("tangent")
    features.update(a for a in variant.vertex_attributes if a.startswith("uv") and a != "uv")  # slots uv1..
    for name, n in variant.counts:
        if n > 0:
            features.add(name)
    if immediates:
        features.add("immediates")
    return features


def uv_slot_names(variant: ShaderVariant) -> dict[str, str]:
    """{{ALBEDO_UV}} ... {{OCCLUSION_UV}}: the vertex output each map samples, "uv<k>" for a ``<map>_uv<k>``
    flag, else "uv"."""
    names = {f"{feature.removesuffix('_map').upper()}_UV": "uv" for feature in TEXTURE_BINDINGS}
    for flag in variant.flags & UV_SLOT_FLAGS.keys():
        feature, k = UV_SLOT_FLAGS[flag]
        names[f"{feature.removesuffix('_map').upper()}_UV"] = f"uv{k}"
    return names


def material_group(instance_data: str) -> int:
    """The material's bind group: 2 after the Object storage group, 1 when instances are vertex attributes."""
    return 2 if instance_data == "storage" else 1


# Per-instance attributes (instance_data "vertex"), after the vertex attributes' locations 0-8: (location, format,
# byte offset in the Object block, the variant flag that needs it or None). The offsets are OBJECT's: the world
# matrix's columns, then the normal matrix's; the third normal column is read as a vec4 whose w is the mirror sign,
# copied into that column's padding (vertex_blocks): 7 attributes, so 9 + 7 fit WebGPU's 16.
INSTANCE_LOCATION = 1 + max(location for location, _ in ATTRIBUTE_LOCATIONS.values())
assert INSTANCE_LOCATION == 9, "shaders_wgsl/scene.wgsl's InstanceIn starts at @location(9)"
_NORMAL = OBJECT.offsets["normal"]
_INSTANCE_ATTRIBUTES = tuple((INSTANCE_LOCATION + c, "float32x4", 16 * c, None) for c in range(4)) + (
    (INSTANCE_LOCATION + 4, "float32x3", _NORMAL, "lighting"),
    (INSTANCE_LOCATION + 5, "float32x3", _NORMAL + 16, "lighting"),
    (INSTANCE_LOCATION + 6, "float32x4", _NORMAL + 32, "lighting"))
_MIRROR_PAD = (_NORMAL + 44) // 4  # the float after the third normal column


def vertex_blocks(blocks: np.ndarray) -> np.ndarray:
    """The Object blocks as the vertex way reads them: the mirror sign also in the third normal column's padding."""
    out = np.array(blocks, dtype=np.float32, copy=True)
    out[:, _MIRROR_PAD] = out[:, OBJECT.offsets["mirror"] // 4]
    return out


def instance_layout(variant: ShaderVariant) -> dict:
    """The vertex buffer of Object blocks, stepped once per instance: only the attributes the variant reads."""
    attributes = [{"shader_location": loc, "format": fmt, "offset": offset}
                  for loc, fmt, offset, flag in _INSTANCE_ATTRIBUTES if flag is None or flag in variant.flags]
    return {"array_stride": OBJECT.size, "step_mode": "instance", "attributes": attributes}


def shader_source(variant: ShaderVariant, immediates: bool, culled: bool = False,
                  instance_data: str = "storage") -> str:
    """scene.wgsl specialised for one variant: only its attributes, bindings, structs and code."""
    objects = [object_struct(variant)] if instance_data == "storage" else []
    structs = [camera_struct(variant), *objects, material_struct(variant)]
    values = {
        "STRUCTS": wgsl_structs(*structs),
        "MATERIAL_GROUP": str(material_group(instance_data)),
        "DIRECTIONAL_LIGHTS": str(variant.count("directional_lights")),
        "POINT_LIGHTS": str(variant.count("point_lights")),
        "PBR_FUNCTIONS": load_wgsl(PBR_FUNCTIONS) if "pbr" in variant.flags else "",
        "IBL_FUNCTIONS": load_wgsl(IBL_FUNCTIONS) if "ibl" in variant.flags else "",
        "CLEARCOAT_FUNCTIONS": load_wgsl(CLEARCOAT_FUNCTIONS) if "clearcoat" in variant.flags else "",
        **uv_slot_names(variant),
    }
    return specialise(load_wgsl(SHADER), shader_features(variant, immediates, culled, instance_data), values,
                      name=SHADER)
