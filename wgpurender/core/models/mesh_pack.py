"""A loaded :class:`~wgpurender.core.models.mesh.Mesh` as bytes and back: what the parse cache stores
(core/models/obj_cached.py) and what a worker process hands its parent (core/models/mesh_workers.py).

Plain arrays behind a fixed header, never pickle: a cache entry is data that cannot run code when it is read
(core/files/cache_entry.py, docs/security.md). Only the meshes a simple OBJ file gives are packed (positions,
normals, uvs, triangle indices, tangents or none, triangle parts); anything else (vertex colours, extra
coordinate slots, points and lines) is not, and :func:`pack` returns None for it. :func:`unpack` checks that the
header's counts match the bytes, so a short or padded blob is refused (None), never read past its end, and that
every index and every part lies within the mesh (a part past its triangles would draw past them).
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from wgpurender.core.models.mesh import Mesh, MeshPart

# magic, vertices, triangles, index bytes (2 or 4), has_uvs, tangents (0 none, 1 file, 2 generated), parts
HEADER = struct.Struct("<8sQQBBBQ")
MAGIC = b"wrmesh1\n"
PART = struct.Struct("<qQQ")  # material (-1: none), first index, index count
TANGENTS = {None: 0, "file": 1, "generated": 2}
SOURCES = {code: name for name, code in TANGENTS.items()}


def pack(mesh: Mesh) -> bytes | None:
    """The mesh as bytes, or None when it holds what a simple OBJ file cannot (see the module docstring)."""
    if (mesh.colors is not None or mesh.extra_uvs or mesh.extra_indices is not None
            or any(p.topology != "triangle-list" for p in mesh.parts)):
        return None
    has_tangents = mesh.tangents is not None
    head = HEADER.pack(MAGIC, len(mesh.positions), len(mesh.indices), mesh.indices.dtype.itemsize, mesh.has_uvs,
                       TANGENTS[mesh.tangents_source] if has_tangents else 0, len(mesh.parts))
    parts = b"".join(PART.pack(-1 if p.material is None else p.material, p.first_index, p.index_count)
                     for p in mesh.parts)
    arrays = [mesh.positions, mesh.normals, mesh.uvs, *([mesh.tangents] if has_tangents else []), mesh.indices]
    return head + parts + b"".join(np.ascontiguousarray(a).tobytes() for a in arrays)


def unpack(blob: bytes | memoryview, source: Path | None, indices_checked: bool = False) -> Mesh | None:
    """The mesh :func:`pack` wrote (its ``source`` set to ``source``), or None when ``blob`` is not one whole.
    ``blob``: bytes (copied: the arrays are writable, as a fresh load's are) or a view of a writable buffer (the
    arrays are views of it: a worker's chunk, copied once for all its meshes). ``indices_checked``: the caller
    already found every index within the vertices (a worker's unpack of the same bytes): not scanned again."""
    if len(blob) < HEADER.size:
        return None
    magic, n, f, index_size, has_uvs, tangents, n_parts = HEADER.unpack_from(blob)
    widths = (3, 3, 2, 4) if tangents else (3, 3, 2)
    at = HEADER.size + n_parts * PART.size
    if magic != MAGIC or index_size not in (2, 4) or tangents not in SOURCES or n == 0 or f == 0 \
            or len(blob) != at + 4 * n * sum(widths) + 3 * f * index_size:
        return None
    parts = tuple(MeshPart(None if m < 0 else m, first, count)
                  for m, first, count in PART.iter_unpack(blob[HEADER.size:at]))
    if any(p.first_index + p.index_count > 3 * f for p in parts):  # a draw of it would read past its triangles
        return None
    if isinstance(blob, bytes):
        blob = bytearray(blob)  # writable arrays, as a fresh load gives
    arrays = []
    for width in widths:
        arrays.append(np.frombuffer(blob, np.float32, n * width, at).reshape(n, width))
        at += 4 * n * width
    indices = np.frombuffer(blob, np.uint16 if index_size == 2 else np.uint32, 3 * f, at).reshape(f, 3)
    if not indices_checked and int(indices.max()) >= n:  # every index within the vertices, as build_mesh checked
        return None
    return Mesh(positions=arrays[0], normals=arrays[1], uvs=arrays[2], indices=indices,
                tangents=arrays[3] if tangents else None, has_uvs=bool(has_uvs), tangents_source=SOURCES[tangents],
                source=source, parts=parts)


def unpack_alike(data: np.ndarray, sources: list[Path | None], indices_checked: bool = False) -> list[Mesh] | None:
    """The meshes :func:`pack` wrote one after another into ``data`` (writable uint8, ``len(sources)`` blobs of
    equal length), as ONE array with a view per mesh and per attribute, when every blob's header and parts are
    the first's (a worker's chunk of similar files: 10k cubes were 5 us each unpacked one by one, issue 31.3);
    None when they are not all alike or the first is not a whole mesh (the caller unpacks each)."""
    count = len(sources)
    if count == 0 or len(data) % count:
        return None
    rows = data.reshape(count, len(data) // count)
    first = unpack(memoryview(rows[0]), sources[0], indices_checked)
    if first is None:
        return None
    at = HEADER.size + len(first.parts) * PART.size
    if not (rows[:, :at] == rows[0, :at]).all():  # the same counts, formats and parts in every blob
        return None
    n, f = len(first.positions), len(first.indices)
    arrays = []
    for width in (3, 3, 2, 4) if first.tangents is not None else (3, 3, 2):
        arrays.append(rows[:, at:at + 4 * n * width].view(np.float32).reshape(count, n, width))
        at += 4 * n * width
    indices = rows[:, at:].view(first.indices.dtype).reshape(count, f, 3)
    if not indices_checked and int(indices.max()) >= n:
        return None
    tangents = arrays[3] if first.tangents is not None else [None] * count
    return [Mesh(positions=p, normals=nrm, uvs=uv, indices=ix, tangents=t, has_uvs=first.has_uvs,
                 tangents_source=first.tangents_source, source=s, parts=first.parts)
            for p, nrm, uv, ix, t, s in zip(arrays[0], arrays[1], arrays[2], indices, tangents, sources,
                                            strict=True)]
