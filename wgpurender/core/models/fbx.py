"""FBX models through assimp (Debian's libassimp5 via the ``pyassimp`` ctypes binding), into the same mesh model.

Chosen over the PyPI ``ufbx`` 0.0.5 binding, which segfaults when Python releases objects it returned
(the team's checked facts say so): pyassimp copies every array into numpy inside ``pyassimp.load``'s context and
releases the scene once, so nothing dangles. assimp 5.2 (Debian 12) applies neither the file's axes nor its
units, so both are applied here from the scene metadata FBX carries (GlobalSettings):

- axes: ``UpAxis``/``FrontAxis``/``CoordAxis`` with their signs map the file's right, up and front onto +x, +y,
  +z (a Blender export, Z up, turns into Y up);
- units: ``UnitScaleFactor`` is centimetres per file unit (1 = cm, 100 = m); positions become metres.

Taken: meshes (triangulated), node transforms (parent @ child), normals (the file's, else smooth), UVs (assimp's
v = 0 at the bottom turned to the mesh convention, v = 0 at the top), tangents (generated, as for every format
without them), and each mesh's own material (diffuse colour, diffuse and normal (or bump) textures: files, or
images embedded in the FBX), one draw per material (core/scene/fbx_materials.py).
"""

from __future__ import annotations

import ctypes
import functools
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail

INSTALL = "`apt-get install libassimp5` and `pip install pyassimp` (make demo installs both)"
TEXTURE_TYPES = {1: "base_color", 6: "normal", 5: "normal"}  # aiTextureType DIFFUSE, NORMALS, HEIGHT (bump)
AI_INT32, AI_FLOAT, AI_DOUBLE = 1, 3, 4


def _assimp():
    try:
        import pyassimp
        import pyassimp.errors
        from pyassimp import postprocess
    except ImportError as err:  # pyassimp raises ImportError too when it finds no libassimp
        raise UserError(f"FBX needs assimp, which is not installed ({err}); {INSTALL}") from None
    return pyassimp, postprocess


def _metadata(scene) -> dict[str, float]:
    """The scene's numeric metadata (FBX GlobalSettings: UnitScaleFactor, UpAxis, ...)."""
    found: dict[str, float] = {}
    pointer = getattr(scene, "metadata", None)
    if not pointer:
        return found
    data = pointer.contents
    types = {AI_INT32: ctypes.c_int32, AI_FLOAT: ctypes.c_float, AI_DOUBLE: ctypes.c_double}
    for i in range(data.mNumProperties):
        key, value = data.mKeys[i], data.mValues[i]
        if value.mType in types:
            name = bytes(key.data[: key.length]).decode("utf-8", "replace")
            found[name] = float(ctypes.cast(value.mData, ctypes.POINTER(types[value.mType])).contents.value)
    return found


def axis_and_unit_matrix(meta: dict[str, float]) -> np.ndarray:
    """4x4: the file's (right, up, front) axes onto (+x, +y, +z), scaled from UnitScaleFactor cm to metres."""
    m = np.zeros((4, 4))
    m[3, 3] = 1.0
    rows = (("CoordAxis", 0, 0), ("UpAxis", 1, 1), ("FrontAxis", 2, 2))
    for key, row, default in rows:
        axis = int(meta.get(key, default))
        if axis not in (0, 1, 2):
            raise UserError(f"FBX GlobalSettings {key} is {axis}; it must be 0, 1 or 2 (x, y or z)")
        m[row, axis] = 1.0 if meta.get(key + "Sign", 1) >= 0 else -1.0
    if abs(np.linalg.det(m[:3, :3])) < 0.5:
        raise UserError("FBX GlobalSettings name one axis twice (UpAxis, FrontAxis, CoordAxis); fix the export")
    scale = float(meta.get("UnitScaleFactor", 1.0)) / 100.0
    if not scale > 0 or not np.isfinite(scale):
        raise UserError(f"FBX UnitScaleFactor {meta.get('UnitScaleFactor')} must be a positive number of cm")
    m[:3, :3] *= scale
    return m


def conversion_text(meta: dict[str, float]) -> str:
    """What axis_and_unit_matrix did, in words (for --explain)."""
    up = "xyz"[int(meta.get("UpAxis", 1))]
    sign = "-" if meta.get("UpAxisSign", 1) < 0 else "+"
    unit = float(meta.get("UnitScaleFactor", 1.0))
    return (f"FBX GlobalSettings: up {sign}{up} turned to +y, UnitScaleFactor {unit:g} cm per unit -> metres "
            f"(x{unit / 100:g})")


def load_fbx(path: Path) -> tuple[list[tuple], dict[int, dict]]:
    """([(world 4x4, positions, faces, normals, uvs or None, mesh name, material index)], materials).

    The materials: the placed meshes' ones by index, each {"name", "color", "textures": {role: name as written},
    "embedded": {name as written: index in the file's embedded textures}, "notes"}. Texture names are resolved
    by the scene's reader (core/scene/fbx_materials.py: the model's folder only)."""
    pyassimp, pp = _assimp()
    flags = pp.aiProcess_Triangulate | pp.aiProcess_JoinIdenticalVertices | pp.aiProcess_SortByPType
    try:
        with read_jail.open_checked(path) as f, pyassimp.load(f, "fbx", processing=flags) as scene:
            meta = _metadata(scene)
            root = axis_and_unit_matrix(meta)
            placed = list(_walk(scene.rootnode, root))
            embedded = {_texture_name(t): i for i, t in enumerate(scene.textures)}
            materials = {k: _material(scene.materials[k].properties, embedded) for k in sorted({p[6] for p in placed})
                         if 0 <= k < len(scene.materials)}
            for material in materials.values():
                material["notes"] = (conversion_text(meta),)
    except UserError:
        raise
    except (pyassimp.errors.AssimpError, Exception) as err:  # AssimpError is a BaseException, not an Exception
        raise UserError(f"cannot read {path} as FBX: {str(err).strip() or type(err).__name__}; re-export it "
                        "(e.g. from Blender as FBX 7.4 binary) or convert it to glTF") from None
    return placed, materials


def _texture_name(texture) -> str:
    """The file name an embedded texture stands for (what a material's texture property names)."""
    name = texture.contents.mFilename
    return bytes(name.data[: name.length]).decode("utf-8", "replace")


def embedded_texture_bytes(path: Path, index: int) -> bytes:
    """The encoded image (PNG, TGA, JPEG ...) of embedded texture ``index`` of an FBX file. assimp keeps an FBX's
    embedded ``Video`` content compressed (height 0, width = its byte count)."""
    stat = path.stat()
    return _embedded_cached(str(path), stat.st_mtime_ns, stat.st_size, index)


@functools.lru_cache(maxsize=8)
def _embedded_cached(path: str, mtime_ns: int, size: int, index: int) -> bytes:
    """One read per image while the file is unchanged: the plan asks each image's size, the upload its pixels."""
    pyassimp, _ = _assimp()
    with read_jail.open_checked(path) as f, pyassimp.load(f, "fbx") as scene:
        if not 0 <= index < len(scene.textures):
            raise UserError(f"{path}: embedded texture {index} does not exist (the file has {len(scene.textures)})")
        texture = scene.textures[index].contents
        if texture.mHeight != 0:
            raise UserError(f"{path}: embedded texture {index} is raw texels, not an encoded image; re-export the "
                            "FBX with its textures as files")
        return ctypes.string_at(texture.pcData, texture.mWidth)


def _walk(node, parent: np.ndarray):
    world = parent @ np.asarray(node.transformation, np.float64)
    for mesh in node.meshes:
        faces = np.asarray(mesh.faces, np.int64)
        if faces.ndim != 2 or faces.shape[1] != 3 or not len(faces):
            continue  # points and lines (SortByPType puts them in meshes of their own)
        positions = np.asarray(mesh.vertices, np.float64)
        normals = np.asarray(mesh.normals, np.float64) if len(mesh.normals) else None
        uvs = None
        if len(mesh.texturecoords):
            uvs = np.asarray(mesh.texturecoords[0], np.float64)[:, :2].copy()
            uvs[:, 1] = 1.0 - uvs[:, 1]  # assimp: v = 0 at the bottom -> the mesh's v = 0 at the top
        yield world, positions, faces, normals, uvs, str(mesh.name), int(mesh.materialindex)
    for child in node.children:
        yield from _walk(child, world)


def _material(props, embedded: dict[str, int]) -> dict:
    textures = {}
    for (key, semantic), value in dict.items(props):  # pyassimp's items() drops the texture type
        role = TEXTURE_TYPES.get(semantic)
        if key == "file" and role is not None and role not in textures:
            textures[role] = str(value)
    color = dict.get(props, ("diffuse", 0))
    return {"name": str(dict.get(props, ("name", 0), "")), "textures": textures,
            "embedded": {n: i for n, i in embedded.items() if n in textures.values()},
            "color": tuple(float(c) for c in color[:3]) if color is not None else None}
