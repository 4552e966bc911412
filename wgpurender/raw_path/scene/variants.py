"""A plan's shader variant as glslc -D flags: the raw path's counterpart of scene.wgsl's "#if feature".

The wgpu path specialises one WGSL template per variant (wgpurender/core/shaders/shader_variants.py keeps the
"#if FEATURE" blocks of the variant's flags); the raw path hands the same decision to glslc's own
preprocessor: each flag becomes a definition (``-DALBEDO_MAP``), the light counts become numbers
(``-DPOINT_LIGHTS=2``), so each variant is its own SPIR-V module, cached by source and flags.
"""

from __future__ import annotations

from wgpurender.core.plan import ShaderVariant
from wgpurender.core.plan.model import TEXTURE_FEATURES, UV_SLOT_FLAGS
from wgpurender.raw_path.device.uniforms import MAX_LIGHTS

FLAGS = ("albedo_map", "normal_map", "roughness_map", "lighting", "flip_v", "srgb_output", "vertex_color",
         "alpha_mask", "double_sided", "emissive", "emissive_map", "occlusion_map", "opaque_alpha", "pbr", "ibl",
         "clearcoat", "clearcoat_map", "clearcoat_roughness_map", "clearcoat_normal_map", *UV_SLOT_FLAGS)
TEXTURE_FLAGS = TEXTURE_FEATURES


def is_lit(variant: ShaderVariant) -> bool:
    return "lighting" in variant.flags


def glsl_defines(variant: ShaderVariant) -> tuple[str, ...]:
    """E.g. ("ALBEDO_MAP", "LIGHTING", "UV", "DIRECTIONAL_LIGHTS=1", "POINT_LIGHTS=2", "MAX_LIGHTS=8")."""
    unknown = variant.flags - set(FLAGS)
    if unknown:
        raise ValueError(f"shader variant flags {sorted(unknown)} have no GLSL definition")  # a plan.py change
    defines = [f.upper() for f in FLAGS if f in variant.flags and f not in UV_SLOT_FLAGS]
    if variant.flags & set(TEXTURE_FLAGS):
        defines.append("UV")
    if "tangent" in variant.vertex_attributes:  # a normal map or a clearcoat normal map: the tangent frame
        defines.append("TANGENT")
    for flag in sorted(variant.flags & UV_SLOT_FLAGS.keys()):  # a map on coordinate slot k: it samples v_uv<k>
        feature, k = UV_SLOT_FLAGS[flag]
        defines.append(f"{feature.removesuffix('_map').upper()}_UV=v_uv{k}")
    defines += sorted({f"UV{UV_SLOT_FLAGS[f][1]}" for f in variant.flags & UV_SLOT_FLAGS.keys()})
    defines += [f"DIRECTIONAL_LIGHTS={variant.count('directional_lights')}",
                f"POINT_LIGHTS={variant.count('point_lights')}", f"MAX_LIGHTS={MAX_LIGHTS}"]
    return tuple(defines)
