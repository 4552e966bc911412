"""The plan's side of KHR_materials_clearcoat: which draws pay for the coat, and its material factors.

"Simulate only the effects a scene calls for": the ``clearcoat`` variant feature (shaders_wgsl/clearcoat.wgsl,
shaders_glsl/clearcoat.glsl) is on only for a lit glTF metallic-roughness material whose coat has a weight
(clearcoatFactor > 0: at 0 the extension says the material behaves as the core one, so it is drawn as that);
each of its three maps adds its own feature, texture and sampler. Everything else stays as it was.
"""

from __future__ import annotations

from wgpurender.core.scene import Material

CLEARCOAT = "clearcoat"
MAPS = {"clearcoat_map": "clearcoatTexture (R channel x clearcoatFactor)",
        "clearcoat_roughness_map": "clearcoatRoughnessTexture (G channel x clearcoatRoughnessFactor)",
        "clearcoat_normal_map": "clearcoatNormalTexture (the coat's own normal)"}


def _has_coat(material: Material) -> bool:
    return material.clearcoat > 0 or any(getattr(material, key) for key in MAPS)


def reasons(material: Material, label: str, lit: bool, notes: list[str]) -> list[tuple[str, str]]:
    """The ``clearcoat`` feature and its maps' features, each with its reason; a coat that cannot apply is a
    note."""
    if not _has_coat(material):
        return []
    if material.clearcoat <= 0:
        notes.append(f"{label}: KHR_materials_clearcoat with clearcoatFactor 0: no coat (the extension's rule), its "
                     "textures are not sampled")
        return []
    if not (lit and material.shading_model == "pbr"):
        notes.append(f"{label}: KHR_materials_clearcoat unused: the coat is a specular layer of lit "
                     "metallic-roughness shading, and this material is drawn unlit")
        return []
    out = [(CLEARCOAT, f"{label}: KHR_materials_clearcoat, clearcoatFactor {material.clearcoat:g}, "
                       f"clearcoatRoughnessFactor {material.clearcoat_roughness:g}: a GGX layer (F0 0.04, the coat's "
                       "normal) over the material, weight clearcoat x Schlick Fresnel")]
    for key, what in MAPS.items():
        path = getattr(material, key)
        if path is not None:
            scale = f", scale {material.clearcoat_normal_scale:g}" if key == "clearcoat_normal_map" else ""
            out.append((key, f"{label}: {what} '{path.name}'{scale}"))
    return out


def factors(material: Material, variant_flags: frozenset[str]) -> dict:
    """The coat's material factors for course.shading.material_factors (nothing without the feature)."""
    if CLEARCOAT not in variant_flags:
        return {}
    return {"clearcoat": (material.clearcoat, material.clearcoat_roughness, material.clearcoat_normal_scale)}
