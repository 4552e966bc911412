"""The final scene's shading constants, material defaults and depth convention.

Both scene renderers (wgpurender/wgpu_path/scene/ on wgpu, wgpurender/raw_path/scene/ on raw
Vulkan) pack these into their own uniform blocks; tests check the images against formulas
written with them.
"""

from __future__ import annotations

import numpy as np

AMBIENT = (0.03, 0.03, 0.035)  # linear ambient radiance, times albedo: faces no light reaches are not black
SPECULAR = 0.04  # dielectric reflectance of the Blinn-Phong lobe
NORMAL_STRENGTH = 1.0  # scales the normal map's tangent-plane components (a material key could set it)

# Material defaults: what a model without a material, or a material without these keys, gets.
DEFAULT_ALBEDO_COLOR = (1.0, 1.0, 1.0, 1.0)
DEFAULT_ROUGHNESS = 0.5
DEFAULT_CLEAR_COLOR = (0.0, 0.0, 0.0, 1.0)  # linear; [render] clear_color

# Reverse-Z: clip z' = w - z, so stored depth' = 1 - depth (1 at near, 0 at far); REVERSE_Z @ perspective(...)
# equals transforms.perspective(..., reverse_z=True). Drawn with depth_compare "greater" and a depth clear of 0.
REVERSE_Z = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, -1.0, 1.0], [0.0, 0.0, 0.0, 1.0]])


def material_factors(albedo_color, roughness: float, lit: bool, has_roughness_map: bool, *,
                     map_scale: float = 1.0, normal_strength: float | None = None,
                     alpha_cutoff: float | None = None, occlusion_strength: float | None = None,
                     metallic: float | None = None, clearcoat=None, emissive=None) -> dict:
    """The per-draw material factors both paths push: with a roughness map, its G channel times ``map_scale`` is
    the roughness (1 for scene materials, glTF's roughnessFactor); unlit materials carry only the base colour.
    A glTF metallic-roughness material's ``metallic`` takes the place of ``specular`` (Blinn-Phong's reflectance).
    Model-file materials append, in this order and only when their variant has the feature: ``alpha_cutoff``,
    ``occlusion_strength``, ``clearcoat`` (factor, roughness, normal scale: KHR_materials_clearcoat), ``emissive``
    (rgb, 0)."""
    values = {"base_color": albedo_color}
    if lit:
        values.update(roughness=map_scale if has_roughness_map else roughness,
                      normal_strength=NORMAL_STRENGTH if normal_strength is None else normal_strength,
                      specular=SPECULAR)
        if metallic is not None:
            del values["specular"]
            values["metallic"] = metallic
    if alpha_cutoff is not None:
        values["alpha_cutoff"] = alpha_cutoff
    if occlusion_strength is not None:
        values["occlusion_strength"] = occlusion_strength
    if clearcoat is not None:
        values.update(zip(("clearcoat", "clearcoat_roughness", "clearcoat_normal_scale"), clearcoat, strict=True))
    if emissive is not None:
        values["emissive"] = (*emissive, 0.0)
    return values
