"""A verified cache entry: the one format of every on-disk cache (SPIR-V, wgpu.h's parse, the pipeline cache).

A cache folder is writable by anyone who can write the user's home (or a restored CI cache, or a shared
$XDG_CACHE_HOME), and a cache that trusts whatever it finds serves an empty, truncated or altered entry. Each
entry is therefore sealed::

    MAGIC | SHA-256 of the key | SHA-256 of the payload | payload length (8 bytes, little-endian) | payload

The key names everything the payload depends on (the source, the compiler's arguments, the driver and library
versions); a lookup with another key, or a payload that does not hash to the recorded digest, is a miss: the
caller computes the value again (the same result: the cache only ever saves time). The hashes detect accidents
and stale entries; they are not a signature: the payloads are data that cannot run code when loaded (SPIR-V is
validated by the driver, the parse is JSON, docs/security.md), so a forged entry can at worst be wrong data of
the right shape. API-free.
"""

from __future__ import annotations

import hashlib
import os
import stat
from pathlib import Path

MAGIC = b"wgpurender-cache-entry-1\n"
HEADER = len(MAGIC) + 32 + 32 + 8
MAX_ENTRY = 256 << 20  # no cache entry of ours is near this: a larger file is not one
_READ_FLAGS = (os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
               | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0))


def _digest(data: bytes | str) -> bytes:
    return hashlib.sha256(data.encode() if isinstance(data, str) else data).digest()


def seal(key: bytes | str, payload: bytes) -> bytes:
    return MAGIC + _digest(key) + _digest(payload) + len(payload).to_bytes(8, "little") + payload


def unseal(blob: bytes, key: bytes | str) -> bytes | None:
    """The payload of ``blob`` if it is a whole entry for ``key``; None otherwise (a miss)."""
    if len(blob) < HEADER or not blob.startswith(MAGIC):
        return None
    at = len(MAGIC)
    if blob[at:at + 32] != _digest(key):
        return None
    length = int.from_bytes(blob[at + 64:HEADER], "little")
    payload = blob[HEADER:]
    if length != len(payload) or blob[at + 32:at + 64] != _digest(payload):
        return None
    return payload


def read_entry(path: Path, key: bytes | str) -> bytes | None:
    """The verified payload at ``path`` (a regular file, not a link elsewhere), or None."""
    try:  # one open and one fstat (a scene of 10k meshes reads 10k entries): no final link, no FIFO waited on
        fd = os.open(path, _READ_FLAGS)
    except (OSError, ValueError):
        return None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode) or info.st_size > MAX_ENTRY:
            return None
        blob = _read(fd, info.st_size + 1)  # one past: a file grown since the fstat is not whole
    except OSError:
        return None
    finally:
        os.close(fd)
    return unseal(blob, key)


def _read(fd: int, most: int) -> bytes:
    """Up to ``most`` bytes of ``fd``, fewer only at its end."""
    parts = []
    while most > 0:
        part = os.read(fd, most)
        if not part:
            break
        parts.append(part)
        most -= len(part)
    return b"".join(parts)


def write_entry(path: Path, key: bytes | str, payload: bytes) -> bool:
    """Store atomically (temp file + rename: a parallel run never reads half an entry); False when the folder
    cannot be written (a read-only home): the cache is only a speed-up. The temp name is guessable, so whatever
    is there (a link planted to a user's file) is removed, never followed: the temp file is created new
    (O_EXCL, which also refuses a link replanted meanwhile)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp.unlink(missing_ok=True)
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o600)
        with os.fdopen(fd, "wb") as f:
            f.write(seal(key, payload))
        os.replace(tmp, path)
        return True
    except OSError:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:
            pass
        return False


def cache_folder(name: str) -> Path:
    """``$XDG_CACHE_HOME/wgpurender/NAME`` (``~/.cache`` when unset): where a cache of ours keeps its entries,
    never beside the user's files. Tests point $XDG_CACHE_HOME at a folder of their own (tests/conftest.py)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "wgpurender" / name
