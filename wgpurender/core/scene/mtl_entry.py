"""One material of an OBJ's MTL library or of an FBX file, as the file says it, and as a scene material.

core/scene/file_materials.py reads MTL files, core/scene/fbx_materials.py an FBX's materials; both end here.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from wgpurender.core.scene.model import Material, Model

MTL_FEATURES = {"base_color": "albedo_map", "normal": "normal_map", "roughness": "roughness_map"}  # drawn roles


@dataclass
class MtlEntry:
    """What an MTL file says of one material: texture files by role, Kd, d (or 1 - Tr) and illum."""

    name: str
    textures: dict[str, Path] = field(default_factory=dict)
    color: tuple[float, float, float] | None = None
    opacity: float | None = None
    illum: int | None = None
    notes: tuple[str, ...] = ()  # what the loader converted (FBX axes and units), for --explain


def entry_material(model: Model, found: MtlEntry, kind: str, part: int | None = None) -> tuple[Material, str, list]:
    """(material, what was taken, what was ignored) of one MTL or FBX material; ``part``: the file's material
    index its triangles are drawn with (None: the whole model)."""
    maps = {MTL_FEATURES[role]: path for role, path in found.textures.items() if role in MTL_FEATURES}
    name = f"{model.label} {kind} material '{found.name}'"
    opacity = 1.0 if found.opacity is None else found.opacity
    material = Material(name, albedo_color=(*(found.color or (1.0, 1.0, 1.0)), opacity), origin=name,
                        alpha_mode="blend" if opacity < 1.0 else "opaque", unlit=found.illum == 0,
                        written=tuple((f, p.name) for f, p in maps.items()), part=part, **maps)
    taken = [f"Kd {material.albedo_color[:3]}"] + [f"{f} {p.name}" for f, p in maps.items()]
    if opacity < 1.0:
        taken.append(f"d {opacity:g} (alpha blended, unsorted)")
    if found.illum == 0:
        taken.append("illum 0 (unlit)")
    taken.extend(found.notes)
    ignored = [f"{kind} '{found.name}': {role} map ignored" for role in found.textures if role not in MTL_FEATURES]
    return material, f"{name}: " + ", ".join(taken), ignored
