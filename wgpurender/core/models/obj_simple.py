"""The common OBJ file read without trimesh's scene machinery: only ``v``, ``vt`` and ``vn`` records and
triangles written ``f a/b/c a/b/c a/b/c``.

That is what wgpurender writes and what most exporters write for a single textured mesh. trimesh reads it
through ``load_scene``: a Scene, a node graph, a Trimesh with its caches, a TextureVisuals. That costs ~0.5 ms
a file, a third of each file's load in a scene of 10k distinct mesh files (issue 31: 17.6 s on the H100). This
reader parses the same records with numpy. It turns each v/vt/vn triplet into a vertex with trimesh's own
``unmerge_faces`` (the function trimesh's OBJ loader calls for such faces), so the arrays equal trimesh's;
tests/test_obj_simple.py compares them with trimesh's path on generated files.

Anything else returns None and the file goes through trimesh and its checks as before. That covers any other
record (a group, ``usemtl``, ``mtllib``, a point or line), a polygon other than a triangle, a corner without its
vt or vn, a negative or out-of-range index, a record with another count of numbers, a line continuation, or a
file over :data:`MAX_BYTES`.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np

from wgpurender.core.files import read_jail

RECORDS = {b"v": 3, b"vt": 2, b"vn": 3}  # numbers per record, exactly
# in a number: trimesh rewrites "+e" and "-e", and Python's float() reads "1_0" where numpy does not
REFUSED = (b"+e", b"-e", b"_")
MAX_BYTES = 1 << 20  # the win is the per-file overhead; a large file goes through trimesh's vectorised parse


def read(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """(positions, faces, normals, uvs as the file writes them: v = 0 at the bottom) of a simple OBJ file, in
    float64 / int64, or None when the file is not one (see the module docstring)."""
    return parse(read_jail.read_checked(path))


def parse(data: bytes) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """:func:`read` of a file's bytes (the parse cache, core/models/obj_cached.py, has read them to hash them)."""
    if len(data) > MAX_BYTES or b"\\" in data:  # a line continuation (trimesh joins the lines, comments too)
        return None
    if not data.isascii():  # trimesh decodes the whole file (a Latin-1 comment is refused there): its verdict rules
        return None
    records: dict[bytes, list[bytes]] = {b"v": [], b"vt": [], b"vn": [], b"f": []}
    for line in data.split(b"\n"):
        line = line.rstrip()  # a trailing \r; leading blanks hide a record from trimesh: refused below
        if not line or line.startswith(b"#"):
            continue
        head, _, rest = line.partition(b" ")
        group = records.get(head)
        if group is None:
            return None
        group.append(rest)
    arrays = {}
    for head, width in RECORDS.items():
        arrays[head] = _numbers(records[head], width, np.float64)
        if arrays[head] is None:
            return None
    faces = _faces(records[b"f"], {head: len(a) for head, a in arrays.items()})
    if faces is None:
        return None
    from trimesh.visual.texture import unmerge_faces

    new_faces, mask_v, mask_vt, mask_vn = unmerge_faces(faces[:, 0::3], faces[:, 1::3], faces[:, 2::3],
                                                        maintain_faces=False)
    return (arrays[b"v"][mask_v], np.asarray(new_faces, np.int64), arrays[b"vn"][mask_vn],
            arrays[b"vt"][mask_vt])


def _numbers(rows: list[bytes], width: int, dtype) -> np.ndarray | None:
    """(len(rows), width) numbers, or None unless every row holds exactly ``width`` of them."""
    text = b" ".join(rows)
    split = [r.split() for r in rows]
    if any(mark in text for mark in REFUSED) or set(map(len, split)) - {width}:
        return None
    try:
        values = np.array(list(map(float, itertools.chain.from_iterable(split))), dtype=dtype)
    except ValueError:
        return None
    return values.reshape(len(rows), width)


def _faces(rows: list[bytes], counts: dict[bytes, int]) -> np.ndarray | None:
    """(triangles, 9) zero-based v, vt, vn indices of each corner, or None unless every face is a triangle of
    three ``a/b/c`` corners with positive indices within the records."""
    split = [r.split() for r in rows]
    if not rows or set(map(len, split)) != {3}:
        return None
    parts = [p for c in itertools.chain.from_iterable(split) for p in c.split(b"/")]
    if len(parts) != 9 * len(rows) or not b"".join(parts).isdigit():  # digits only: no sign, no "_"
        return None
    try:
        faces = np.array(list(map(int, parts)), dtype=np.int64).reshape(len(rows), 9) - 1
    except ValueError:  # an empty index ("1//1")
        return None
    limits = np.array([counts[b"v"], counts[b"vt"], counts[b"vn"]] * 3)
    if faces.min() < 0 or np.any(faces >= limits):
        return None
    return faces
