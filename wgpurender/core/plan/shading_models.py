"""Which material model a draw shades with, and why: the course's Blinn-Phong or glTF's metallic-roughness.

"Simulate only the effects a scene calls for": the ``pbr`` shader variant (scene.wgsl with pbr.wgsl; scene.frag
with pbr.glsl) is built only for a lit material of a glTF file, whose author chose the metallic-roughness model
(the only one glTF 2.0 defines; its Appendix B BRDF). The course's scene materials, OBJ/MTL materials and glTF
primitives without a material keep the Blinn-Phong the course teaches. ``--explain`` gives each lit material's
model with its reason: a ``pbr`` variant reason, or a note for Blinn-Phong.
"""

from __future__ import annotations

from wgpurender.core.scene import Material

PBR = "pbr"
BLINN_PHONG = "blinn-phong"


def uses_pbr(material: Material, lit: bool) -> bool:
    return lit and material.shading_model == PBR


def model_reasons(material: Material, label: str, lit: bool, has_metal_map: bool,
                  notes: list[str]) -> list[tuple[str, str]]:
    """The ``pbr`` variant feature with its reason, or (lit Blinn-Phong) a note saying why not."""
    if uses_pbr(material, lit):
        metal = " x the metallic-roughness texture's B channel" if has_metal_map else ""
        return [(PBR, f"{label} is a glTF metallic-roughness material: metallicFactor {material.metallic:g}{metal}, "
                      "GGX / Smith / Schlick BRDF (glTF 2.0 Appendix B, shaders_wgsl/pbr.wgsl)")]
    if lit:
        why = ("primitives without a glTF material get the default material" if material.part == -1
               else "the course's model for its own materials")
        notes.append(f"{label} shades with the course's Blinn-Phong ({why}; the metallic-roughness variant is built "
                     "only for a glTF file's lit materials)")
    return []


def metallic_factor(material: Material, variant_flags: frozenset[str]) -> dict:
    """The ``metallic`` material factor of a ``pbr`` variant (nothing otherwise)."""
    return {"metallic": material.metallic} if PBR in variant_flags else {}
