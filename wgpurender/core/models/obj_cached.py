"""Simple OBJ files through a verified parse cache: a warm load of a scene of thousands of mesh files reads each file's
mesh back instead of parsing it again (issue 31: the Python parse was most of a distinct file's load).

Content-addressed: the key is the SHA-256 of the file's bytes, whether tangents were made, and the parser's version,
which is a hash of the source of every module the result depends on (this one, obj_simple, mesh, tangents,
mesh_pack) and of the numpy, trimesh and wgpurender versions (trimesh's ``unmerge_faces`` orders the vertices). So
an edited file, an edited parser or another library version is a miss, never a stale mesh. An entry is a sealed
cache entry (core/files/cache_entry.py: verified before use, written atomically by a process that reads a small scene
itself) holding a packed mesh (core/models/mesh_pack.py: arrays, no pickle), in ``$XDG_CACHE_HOME/wgpurender/meshes``,
never in the user's folder; worker processes store a whole chunk of files as one entry there
(core/models/obj_cached_chunks.py). Only files the simple reader takes are cached:
their bytes are all they depend on (no MTL, no texture); anything else goes through the general loader every time. A
cache that cannot be written is only slower.
"""

from __future__ import annotations

import functools
import hashlib
import os
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from wgpurender.core.files import read_jail
from wgpurender.core.files.cache_entry import cache_folder, read_entry, write_entry
from wgpurender.core.files.input_files import check_file_size, check_size, input_file
from wgpurender.core.models import mesh, mesh_pack
from wgpurender.core.models.mesh import Mesh, mesh_of_parts, simple_obj_parts

CODE = ("obj_cached.py", "obj_cached_chunks.py", "obj_simple.py", "mesh.py", "tangents.py", "mesh_pack.py")
LIBRARIES = ("numpy", "trimesh", "wgpurender")


@functools.cache
def parser_version() -> str:
    """A hash of the parser's own source and library versions: any change makes every old entry a miss."""
    digest = hashlib.sha256()
    for name in CODE:
        try:
            digest.update((Path(__file__).parent / name).read_bytes())
        except OSError:  # an install without sources: its package version below stands for them
            digest.update(f"{name} unreadable".encode())
    for name in LIBRARIES:
        try:
            digest.update(f"{name} {version(name)}".encode())
        except PackageNotFoundError:
            digest.update(f"{name} absent".encode())
    return digest.hexdigest()


def folder() -> Path:
    return cache_folder("meshes")


def entry_key(data: bytes, generate_tangents: bool) -> str:
    return (f"simple OBJ mesh; parser {parser_version()}; tangents {int(generate_tangents)}; "
            f"file sha256 {hashlib.sha256(data).hexdigest()}")


def entry_path(where: Path, key: str) -> Path:
    return where / f"{hashlib.sha256(key.encode()).hexdigest()[:40]}.mesh"


def load_mesh(path: str | os.PathLike, *, generate_tangents: bool = True, pose=None, store: bool = True) -> Mesh:
    """:func:`wgpurender.core.models.mesh.load_mesh` through the parse cache: what a scene's models load with
    (core/plan/meshes.py). An OBJ file gets load_mesh's checks (a readable regular file within the size limit),
    then its mesh from :func:`load` (``store``: an entry is written for what is parsed); any other file (or pose:
    glTF animation), or an OBJ the simple reader does not take, load_mesh's."""
    path = Path(path)
    if path.suffix.lower() == ".obj" and pose is None:  # a pose is a glTF animation's: never an OBJ's
        check_file_size(input_file(path, "model file"), "model file")
        found = load(path, generate_tangents, folder(), store)
        if found is not None:
            return found
    return mesh.load_mesh(path, generate_tangents=generate_tangents, pose=pose)


def load(path: Path, generate_tangents: bool, where: Path | None, store: bool = True) -> Mesh | None:
    """The mesh of the simple OBJ file ``path``: the cache's (in folder ``where``; None: no cache) when it holds
    a whole entry for these bytes, else parsed (and stored when ``store``); None when the file is not simple (the
    caller loads it the general way)."""
    mesh, _ = _load(path, generate_tangents, where, store)
    return mesh


def parse_packed(path: Path, data: bytes, generate_tangents: bool) -> tuple[Mesh | None, bytes | None]:
    """(mesh, packed) of a simple OBJ file's bytes, parsed (no cache); (None, None) when the file is not simple.
    What a miss costs: here and in a worker (core/models/obj_cached_chunks.py, which stores whole chunks)."""
    parts = simple_obj_parts(data)
    if parts is None:
        return None, None
    mesh = mesh_of_parts(path, parts, generate_tangents)
    return mesh, mesh_pack.pack(mesh)


def _load(path: Path, generate_tangents: bool, where: Path | None,
          store: bool) -> tuple[Mesh | None, bytes | None]:
    """(mesh, packed). Creating an entry's file costs ~0.5 ms of system time on the H100 host and on the lavapipe
    host (2026-11-27, docs/perf-h100/2026-11-27-load: 10,000 entries from one process made a cold load 1.65x
    slower than no cache), more than a small file's parse, so a caller reading many files in one process passes
    ``store=False`` (core/plan/meshes.py)."""
    # the file the scene's read rule checked, still that file, within the size limit (input_file's checks)
    data = read_jail.read_checked(path, functools.partial(check_size, path, what="model file"))
    entry = key = None
    if where is not None:
        key = entry_key(data, generate_tangents)
        entry = entry_path(where, key)
        payload = read_entry(entry, key)
        mesh = None if payload is None else mesh_pack.unpack(payload, path)
        if mesh is not None:
            return mesh, payload
    mesh, packed = parse_packed(path, data, generate_tangents)
    if store and entry is not None and packed is not None:
        write_entry(entry, key, packed)
    return mesh, packed
