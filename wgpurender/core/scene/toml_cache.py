"""A large scene file's TOML, parsed once: a verified cache of what ``tomllib.loads`` returned, as JSON.

tomllib is pure Python: a scene of 10k ``[[models]]`` tables (~440 KB) took ~100 ms to parse, more than a tenth
of issue 31.3's 1 s load, where reading the same values back as JSON takes ~4 ms. So a scene text of at least
:data:`MIN_CHARS` characters is parsed once and its values kept in a sealed entry (core/files/cache_entry.py:
verified before use, written atomically) under ``$XDG_CACHE_HOME/wgpurender/scenes``, never beside the scene.

Content-addressed: the key is the SHA-256 of the text and the Python version (whose tomllib parsed it), so an
edited scene is a miss, never stale values. JSON holds exactly what TOML gives a scene (strings, integers,
floats with repr's round trip, inf and nan included, booleans, arrays, tables in their order); a scene holding
TOML dates or times is not cached. The values read back are validated as every scene's are (core/scene/
validate.py), so an entry can at worst be the values of another text of the right shape, never run code. Smaller
scenes (every bundled one) are parsed each time: no cache file for them.
"""

from __future__ import annotations

import hashlib
import json
import sys
import tomllib
from pathlib import Path

from wgpurender.core.files.cache_entry import cache_folder, read_entry, write_entry

MIN_CHARS = 64 * 1024  # ~1,500 [[models]] tables: below this a parse is a few ms, less than an entry's read


def loads(text: str) -> dict:
    """``tomllib.loads(text)``, from the cache when it holds this text (raises TOMLDecodeError as tomllib does)."""
    if len(text) < MIN_CHARS:
        return tomllib.loads(text)
    key = f"scene TOML as JSON; python {sys.version}; text sha256 {hashlib.sha256(text.encode()).hexdigest()}"
    entry = folder() / f"{hashlib.sha256(key.encode()).hexdigest()[:40]}.json"
    cached = _values(read_entry(entry, key))
    if cached is not None:
        return cached
    data = tomllib.loads(text)
    try:
        payload = json.dumps(data, allow_nan=True).encode()
    except (TypeError, ValueError, RecursionError):  # dates and times have no JSON form: parsed each time
        return data
    write_entry(entry, key, payload)
    return data


def _values(payload: bytes | None) -> dict | None:
    if payload is None:
        return None
    try:
        data = json.loads(payload)
    except (ValueError, RecursionError):
        return None
    return data if isinstance(data, dict) else None


def folder() -> Path:
    return cache_folder("scenes")
