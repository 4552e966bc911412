"""A worker's chunk of simple OBJ files through the parse cache as ONE sealed entry (issue 31: a cold load of
10,000 distinct files made 10,000 entry files, a create and a rename each, from 16 workers into one folder; the
H100 host's cold load took 3.4 s more than its warm one).

The key names the parser (:func:`obj_cached.parser_version`) and, in order, each file's SHA-256 and whether its
tangents are made, so a lookup is a hit only for the same bytes in the same chunk: the same scene on the same
machine (the chunks follow the file count and the worker count, core/models/mesh_workers.py). An edited file
misses its own chunk only, whose files are then parsed again. The payload::

    MAGIC | file count (8 bytes) | each file's packed length (8 bytes each; < 0: not a simple OBJ) | packed meshes

Verified before use: the sealed entry (core/files/cache_entry.py: key, digest, length, owner), the count and the
lengths against the bytes, and every mesh unpacked with its indices checked (core/models/mesh_pack.py); anything
else is a miss. Written atomically by the worker that parsed the chunk (one file per chunk), never in the user's
folder; a chunk with a refused file is not stored, and a cache that cannot be written is only slower.
"""

from __future__ import annotations

import hashlib
import struct
from pathlib import Path

from wgpurender.core.errors import UserError
from wgpurender.core.files.cache_entry import MAX_ENTRY, read_entry, write_entry
from wgpurender.core.models import mesh_pack, obj_cached

MAGIC = b"wrchunk1"
HEAD = struct.Struct("<8sQ")
File = tuple[Path, bool, bytes]  # (model file, make tangents, its bytes)
Packed = bytes | None | UserError  # a packed mesh, None (not a simple OBJ), or the file's refusal


def meshes(files: list[File], where: Path | None) -> list[Packed]:
    """Each file's packed mesh, from the chunk's entry in folder ``where`` when it holds a whole one, else parsed
    (and stored when no file was refused); ``where`` None: no cache. Every mesh returned has had its indices
    checked (built here, or unpacked from the entry)."""
    key = None if where is None else chunk_key(files)
    found = None if key is None else lookup(where, key, files)
    if found is not None:
        return found
    packed = [_parsed(path, tangents, data) for path, tangents, data in files]
    if key is not None and not any(isinstance(p, UserError) for p in packed):
        store(where, key, packed)
    return packed


def _parsed(path: Path, tangents: bool, data: bytes) -> Packed:
    try:
        return obj_cached.parse_packed(path, data, tangents)[1]
    except UserError as err:
        return err


def chunk_key(files: list[File]) -> str:
    names = "; ".join(f"{int(tangents)} {hashlib.sha256(data).hexdigest()}" for _, tangents, data in files)
    return f"simple OBJ meshes of a chunk; parser {obj_cached.parser_version()}; files {names}"


def entry_path(where: Path, key: str) -> Path:
    return where / f"{hashlib.sha256(key.encode()).hexdigest()[:40]}.meshes"


def encode(packed: list[bytes | None]) -> bytes:
    lengths = [-1 if p is None else len(p) for p in packed]
    return (HEAD.pack(MAGIC, len(packed)) + struct.pack(f"<{len(packed)}q", *lengths)
            + b"".join(p for p in packed if p is not None))


def decode(payload: bytes, count: int) -> list[bytes | None] | None:
    """The ``count`` packed meshes (or None each) :func:`encode` wrote, or None when ``payload`` is not one whole
    chunk of ``count`` files (another count, a length out of range, bytes short or left over)."""
    at = HEAD.size + 8 * count
    if len(payload) < at or HEAD.unpack_from(payload) != (MAGIC, count):
        return None
    lengths = struct.unpack_from(f"<{count}q", payload, HEAD.size)
    if at + sum(n for n in lengths if n > 0) != len(payload):
        return None
    out: list[bytes | None] = []
    for n in lengths:
        out.append(None if n < 0 else payload[at:at + n])
        at += max(n, 0)
    return out


def lookup(where: Path, key: str, files: list[File]) -> list[Packed] | None:
    """The chunk's packed meshes from its entry, each unpacked here (its indices checked), or None: a miss."""
    payload = read_entry(entry_path(where, key), key)
    found = None if payload is None else decode(payload, len(files))
    if found is None:
        return None
    for packed, (path, _, _) in zip(found, files, strict=True):
        if packed is not None and mesh_pack.unpack(packed, path) is None:
            return None
    return found


def store(where: Path, key: str, packed: list[bytes | None]) -> bool:
    """Write the chunk's entry (one file); False when it cannot be written or would be too large to be read back."""
    size = HEAD.size + 8 * len(packed) + sum(len(p) for p in packed if p is not None)
    if size + 1024 > MAX_ENTRY:  # read_entry refuses a file over MAX_ENTRY (it would only ever be a miss): not
        return False  # encoded either, so a chunk of large meshes is never held twice for nothing
    return write_entry(entry_path(where, key), key, encode(packed))
