"""An FBX file's materials as scene materials: one per material its meshes use, each drawn over its own triangles.

assimp (core/models/fbx.py) gives each mesh its material index and each material its diffuse colour and texture
names as the exporting tool wrote them. Real files name textures in three ways, each handled here:

- an image embedded in the FBX (``Video`` content; 3ds Max and Maya "embed media"): drawn from the file itself,
  as ``model.fbx#images[k]`` (the same mark as a glTF's embedded images, gltf_materials.embedded_image_bytes);
- a path relative to the model inside its folder: read through the read jail (core/files/read_jail.py);
- a path that is absolute or leads out of the folder (``D:\\projects\\...\\tex.jpg``, ``..\\..\\Desktop\\uv.png``:
  the exporting machine's): never followed; the file of that name beside the model is read instead, as assimp's
  viewer and Blender do, and ``--explain`` says so. Not there either: the texture is ignored, by name.
"""

from __future__ import annotations

from pathlib import Path, PureWindowsPath

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail
from wgpurender.core.scene.gltf_materials import embedded_image_path
from wgpurender.core.scene.model import Model, ModelMaterials
from wgpurender.core.scene.mtl_entry import MtlEntry, entry_material


def fbx_materials(model: Model) -> ModelMaterials | None:
    """The materials of the FBX's placed meshes (``part``: the file's material index), or None without any."""
    from wgpurender.core.models import fbx

    _, found = fbx.load_fbx(model.path)
    if not found:
        return None
    materials, taken, ignored = [], [], []
    for index, entry in sorted(found.items()):
        notes: list[str] = []
        textures = {role: texture_file(model.path, written, entry["embedded"], notes)
                    for role, written in entry["textures"].items()}
        textures = {role: path for role, path in textures.items() if path is not None}
        mtl = MtlEntry(entry["name"], textures, entry["color"], notes=tuple(entry.get("notes", ())))
        material, said, skipped = entry_material(model, mtl, "FBX", part=index)
        materials.append(material)
        taken.append(said)
        ignored.extend(skipped + [f"FBX '{entry['name']}': {note}" for note in notes if "ignored" in note])
        taken.extend(f"FBX '{entry['name']}': {note}" for note in notes if "ignored" not in note)
    return ModelMaterials(tuple(materials), tuple(taken), tuple(ignored))


def texture_file(model: Path, written: str, embedded: dict[str, int], notes: list[str]) -> Path | None:
    """The image an FBX texture name stands for (see the module docstring), or None (said in ``notes``)."""
    if written in embedded:
        notes.append(f"texture '{written}' embedded in the FBX (image {embedded[written]})")
        return embedded_image_path(model.resolve(), embedded[written])
    target = _inside(model, written.replace("\\", "/"))
    if target is not None:
        return target
    base = PureWindowsPath(written).name
    beside = _inside(model, base) if base else None
    if beside is not None:
        notes.append(f"texture '{written}' is outside the model's folder: read {base} beside the model")
        return beside
    notes.append(f"texture '{written}' not found in the model's folder (nor {base or 'its name'} beside the "
                 "model): ignored")
    return None


def _inside(model: Path, name: str) -> Path | None:
    """An existing file ``name`` relative to the model, inside the model's folder; None otherwise."""
    try:
        target = read_jail.model_file(model, name, "FBX texture", encoded=False)
    except UserError:
        return None  # absolute, a drive, or out of the folder: never followed
    return target if target.is_file() else None
