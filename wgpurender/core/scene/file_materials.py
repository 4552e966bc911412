"""A model file's own materials, read once when the scene loads (issue 32 item 2: the plan never opens a model).

A model whose scene entry names no material draws with its file's materials: a glTF's (core/scene/gltf_materials.py
maps them) or an OBJ's first ``usemtl`` material from its MTL library (here). :func:`read_file_materials` is what
:func:`wgpurender.core.scene.load_scene` stores on each such :class:`~wgpurender.core.scene.Model`
(``file_materials``); the plan reads that, never the file.
"""

from __future__ import annotations

import logging
import os
import re
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail
from wgpurender.core.scene.fbx_materials import fbx_materials
from wgpurender.core.scene.gltf_materials import model_materials
from wgpurender.core.scene.model import Model, ModelMaterials
from wgpurender.core.scene.mtl_entry import MtlEntry, entry_material

GLTF_SUFFIXES = (".gltf", ".glb")
MTL_ROLES = {"map_kd": "base_color", "map_bump": "normal", "bump": "normal", "norm": "normal",
             "map_pr": "roughness", "map_ao": "occlusion", "map_ke": "emissive"}  # MTL statement -> texture role

log = logging.getLogger(__name__)


def read_file_materials(model: Model) -> ModelMaterials | None:
    """The materials ``model`` draws with from its file (None: the scene's material; an OBJ without an MTL)."""
    if not model.material_from_file:
        return None
    if model.suffix in GLTF_SUFFIXES:
        return model_materials(model.path, model.label)
    if model.suffix in (".obj", ".fbx"):
        return obj_materials(model)
    return None


def obj_materials(model: Model) -> ModelMaterials | None:
    """An OBJ's MTL material (its first ``usemtl``) as a scene material: Kd x map_Kd (sRGB), the bump/norm map as
    normal map, map_Pr as roughness map, d (or 1 - Tr) as the base colour's alpha, illum 0 as unlit; None without
    an MTL. An FBX's materials (one per material its meshes use): core/scene/fbx_materials.py, the same way."""
    if model.suffix == ".fbx":
        return fbx_materials(model)
    found = obj_mtl_entry(model.path)
    if found is None:
        return None
    material, taken, ignored = entry_material(model, found, "MTL")
    used = dict.fromkeys(re.findall(rb"^[ \t]*usemtl[ \t]+(.+?)[ \t]*$", read_jail.read_checked(model.path), re.M))
    if len(used) > 1:
        ignored.append(f"usemtl {', '.join(repr(u.decode('utf-8', 'replace')) for u in list(used)[1:])}: ignored "
                       f"(an OBJ draws with its first material, '{found.name}')")
    return ModelMaterials((material,), (taken,), tuple(ignored))


def obj_mtl_entry(path: Path) -> MtlEntry | None:
    """The material of the first ``usemtl`` in an OBJ, with the texture files its MTL names (paths resolved)."""
    text = read_jail.read_checked(path)
    libraries = re.findall(rb"^[ \t]*mtllib[ \t]+(.+?)[ \t]*$", text, re.M)
    used = re.search(rb"^[ \t]*usemtl[ \t]+(.+?)[ \t]*$", text, re.M)
    wanted = used.group(1).decode("utf-8", "replace") if used else None
    for lib in libraries:
        mtl = read_jail.model_file(path, lib.decode("utf-8", "replace"), "mtllib", encoded=False)
        if not os.path.isfile(mtl):
            # info, not warning: a missing MTL is legal (the model loads untextured) and must not add stderr lines
            log.info("%s: material library %s not found; loading without textures", path, mtl)
            continue
        materials = parse_mtl(mtl, path)
        if wanted in materials:
            return materials[wanted]
        if wanted is None and materials:
            return next(iter(materials.values()))
    return None


def parse_mtl(path: Path, model: Path | None = None) -> dict[str, MtlEntry]:
    """Every material in the MTL file of OBJ ``model`` (default: the MTL's own folder is the model's). Map options
    (``-bm 1.0`` ...) are skipped: the file name is the rest (:func:`map_file_name`). Paths are resolved relative to
    the MTL file and must stay in the model's folder (core/files/read_jail.py)."""
    materials: dict[str, MtlEntry] = {}
    current = None
    for number, raw in enumerate(read_jail.read_checked(path).decode("utf-8", "replace").splitlines(), start=1):
        tokens = raw.strip().split()
        if not tokens or tokens[0].startswith("#"):
            continue
        key = tokens[0].lower()
        if key == "newmtl":
            current = MtlEntry(" ".join(tokens[1:]))
            materials[current.name] = current
        elif key in MTL_ROLES and current is not None and len(tokens) > 1:
            name = map_file_name(raw)
            if not name.isprintable():
                raise UserError(f"{path}:{number}: texture path {name!r} contains a control character; "
                                "fix the material library")
            where = f"{path}:{number} {tokens[0]}"
            texture = read_jail.model_file(model or path, name, where, base=path.parent, encoded=False)
            current.textures.setdefault(MTL_ROLES[key], texture)
        elif key in ("kd", "d", "tr", "illum") and current is not None:
            _mtl_number(current, key, tokens[1:], f"{path}:{number}")
    return materials


def _mtl_number(entry: MtlEntry, key: str, values: list[str], where: str) -> None:
    """Kd r g b (a single value means grey), d / Tr (opacity, transparency) and illum; a bad number is one line."""
    try:
        numbers = [float(v) for v in values[:3]]
    except ValueError:
        raise UserError(f"{where}: {key.capitalize()} needs numbers, got {' '.join(values)!r}; fix the material "
                        "library") from None
    if not numbers or not all(np.isfinite(numbers)):
        raise UserError(f"{where}: {key.capitalize()} needs finite numbers; fix the material library")
    if key == "kd":
        entry.color = tuple(max(0.0, v) for v in (numbers * 3)[:3])
    elif key == "illum":
        entry.illum = int(numbers[0])
    else:
        entry.opacity = min(1.0, max(0.0, numbers[0] if key == "d" else 1.0 - numbers[0]))


# a map statement's options and how many values each takes (-o, -s, -t: 1 to 3 numbers)
MAP_OPTIONS = {"-blendu": 1, "-blendv": 1, "-boost": 1, "-mm": 2, "-texres": 1, "-clamp": 1, "-bm": 1,
               "-imfchan": 1, "-type": 1, "-cc": 1, "-o": 3, "-s": 3, "-t": 3}


def map_file_name(line: str) -> str:
    """The file name of an MTL map statement: what follows its options, spaces kept (Blender writes a name with
    spaces unquoted: ``map_Kd -bm 1.0 my brick.png``)."""
    tokens = line.split()
    k = 1
    while k < len(tokens) - 1 and tokens[k].lower() in MAP_OPTIONS:
        most, k = MAP_OPTIONS[tokens[k].lower()], k + 1
        for taken in range(most):
            if k >= len(tokens) - 1 or (most == 3 and taken and not _is_number(tokens[k])):
                break
            k += 1
    return line.strip().split(None, k)[-1]


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
