"""The plan's side of a model file's own materials: which materials a model draws with, the variant features and
pipeline state they add, and each texture's sampler. The materials were read when the scene loaded
(core/scene/file_materials.py, ``Model.file_materials``): the plan never opens a model file.

A model whose scene entry names no material and whose file is glTF draws one draw per file material its
triangles use (``Draw.part``); every other model draws once with its scene material, as before.
"""

from __future__ import annotations

from wgpurender.core.plan import clearcoat
from wgpurender.core.plan.shading_models import metallic_factor
from wgpurender.core.scene import Material, Model
from wgpurender.core.scene.model import ModelMaterials


def draw_materials(model: Model) -> tuple[list[Material], ModelMaterials | None]:
    """The materials ``model`` is drawn with (one draw each) and, for a model file's own, what was taken/ignored."""
    found = model.file_materials
    if found is not None:
        return list(found.materials), found
    return [model.material], None


def extra_reasons(material: Material, label: str, lit: bool, samples: bool, notes: list[str]) -> list[tuple]:
    """Variant features a model file's material adds (none for scene materials): vertex colours, alpha mask, the
    back-face normal flip of a lit double-sided material."""
    reasons = []
    if material.vertex_colors:
        reasons.append(("vertex_color", f"{label}: the model's primitives have COLOR_0 (multiplies the base colour)"))
    if material.alpha_mode == "mask":
        reasons.append(("alpha_mask", f"{label}: alphaMode MASK, alphaCutoff {material.alpha_cutoff:g} "
                                      "(fragments with a lower alpha are discarded, the rest written opaque)"))
    elif material.part is not None and material.alpha_mode == "opaque" and _alpha_varies(material):
        reasons.append(("opaque_alpha", f"{label}: alphaMode OPAQUE with an alpha below 1 in its base colour "
                                        "factor, texture or vertex colours: written with alpha 1 (glTF ignores it)"))
    if material.double_sided and lit:
        reasons.append(("double_sided", f"{label}: doubleSided, lit: back faces are lit with the normal turned "
                                        "around"))
    if any(c > 0 for c in material.emissive_color):
        reasons.append(("emissive", f"{label}: emissiveFactor {tuple(material.emissive_color)} (added to the "
                                    "shaded colour)"))
        if material.emissive_map:
            reasons.append(("emissive_map", f"{label}: emissiveTexture '{material.emissive_map.name}' "
                                            "(sRGB, multiplies emissiveFactor)"))
    elif material.emissive_map:
        notes.append(f"{label}: emissiveTexture ignored: emissiveFactor is 0, so it emits nothing")
    if material.occlusion_map:
        if lit:
            reasons.append(("occlusion_map", f"{label}: occlusionTexture '{material.occlusion_map.name}' (R "
                                             f"channel, strength {material.occlusion_strength:g}, scales the "
                                             "ambient term)"))
        else:
            notes.append(f"{label}: occlusionTexture unused: it scales the ambient term of lit shading only")
    return reasons + clearcoat.reasons(material, label, lit, notes)


def uv_slot_reasons(material: Material, label: str, reasons: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """``<feature>_uv<k>`` for each sampled texture of the material on the mesh's coordinate slot k >= 1 (a glTF
    texCoord or KHR_texture_transform of its own): only such variants read vertex attribute uv<k>."""
    sampled = {feature for feature, _ in reasons}
    return [(f"{feature}_uv{k}", f"{label}: its {feature} samples {how}: the mesh's coordinate slot {k} (vertex "
                                 f"attribute uv{k})") for feature, k, how in material.uv_slots if feature in sampled]


def _alpha_varies(material: Material) -> bool:
    """Whether a file material's base colour can carry an alpha below 1 (factor, texture or COLOR_0)."""
    return material.albedo_color[3] < 1.0 or material.albedo_map is not None or material.vertex_colors


def pipeline_state(material: Material) -> dict:
    """ScenePipeline fields a material decides: culling (doubleSided), blending (alphaMode BLEND) and the
    topology (glTF points and lines)."""
    return {"cull_mode": "none" if material.double_sided else "back", "blend": material.alpha_mode == "blend",
            "topology": material.topology}


def factor_options(material: Material, variant_flags: frozenset[str]) -> dict:
    """Keyword arguments of course.shading.material_factors beyond the scene keys."""
    options = {"map_scale": material.roughness_map_scale, "normal_strength": material.normal_strength}
    if "alpha_mask" in variant_flags:
        options["alpha_cutoff"] = material.alpha_cutoff
    if "occlusion_map" in variant_flags:
        options["occlusion_strength"] = material.occlusion_strength
    if "emissive" in variant_flags:
        options["emissive"] = tuple(material.emissive_color)
    return options | metallic_factor(material, variant_flags) | clearcoat.factors(material, variant_flags)


def texture_samplers(material: Material, sampled: tuple[tuple[str, object], ...], spec) -> tuple:
    """(feature, SamplerSpec) per sampled texture: the file's sampler of each texture, else the material's one."""
    own = dict(material.texture_samplers)
    return tuple((feature, own.get(feature, spec)) for feature, _ in sampled)


def texture_mipmaps(material: Material, feature: str) -> bool:
    return dict(material.texture_mipmaps).get(feature, material.sampler.mipmaps)


def model_notes(model: Model, found: ModelMaterials) -> list[str]:
    """``--explain`` lines: what was taken from the model file and what was ignored."""
    def short(item: str) -> str:
        return item.removeprefix(model.label).strip()

    lines = [f"{model.label}: from the model file (the scene gives no material): {short(t)}" for t in found.taken]
    lines += [f"{model.label}: {short(item)}" for item in found.ignored]
    return lines
