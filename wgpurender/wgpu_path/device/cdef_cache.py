"""wgpu.h parsed once per machine instead of once per process: the largest part of wgpu's context set-up.

Importing wgpu-py's wgpu-native backend runs ``ffi.cdef(wgpu.h)``: cffi parses the whole header with
pycparser (~440 typedefs, ~200 functions, ~600 constants), 0.4-1.7 s per process here and most of the
first pixel's gap to raw Vulkan (issue 22.5, docs/benchmarks.md). The result of that parse is plain data
in cffi's parser (``ffi._parser``: declarations as ``cffi.model`` types, integer constants), so the first
process stores it and later ones load it instead of parsing. It is stored as JSON (cdef_json.py), never as a
pickle: loading a pickle runs code, so anyone who could write the cache folder ran code as the user (issue
28.8). The file is a verified cache entry (core/files/cache_entry.py): empty, truncated, altered or keyed for other
versions, it is a miss, and the header is parsed again.

What a second run of the same command finds, no more: the file lives in ``$XDG_CACHE_HOME/wgpurender``
(``~/.cache``), keyed by the header's SHA-256 and the cffi, pycparser and Python versions, so a new
wgpu-py, cffi or Python parses afresh. ``cffi.FFI.cdef`` is replaced only while wgpu's backend is being
imported (:func:`cached_wgpu_header`), and only a cdef of wgpu's header (no options) takes the cached
path; anything unexpected (a cffi without these internals, an unreadable or stale file, a parse that left
work for the backend) falls back to the real parse. tests/test_cdef_cache.py compares a restored parser
with a real parse, type by type, in fresh processes. This uses cffi internals, as cffi_types.py does.
"""

from __future__ import annotations

import hashlib
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from wgpurender.core.files.cache_entry import cache_root
from wgpurender.wgpu_path.device.wgpu_private import BACKEND_FFI  # the module whose import parses wgpu.h

# The parser attributes a parse fills (cffi.cparser.Parser.__init__); _structnode2type only serves the parse.
STATE = ("_declarations", "_included_declarations", "_anonymous_counter", "_options", "_int_constants",
         "_uses_new_feature")
status = "not used"  # "restored", "parsed and saved", "parsed" (could not save), or "not used": for tests and bench


def cache_dir() -> Path:
    return cache_root()


def cache_file(csource: str) -> Path:
    import cffi

    from wgpurender.wgpu_path.device.parser_on_demand import version

    versions = f"cffi {cffi.__version__} pycparser {version()} python {sys.version_info[:3]}"
    digest = hashlib.sha256((versions + "\n" + csource).encode()).hexdigest()[:24]
    return cache_dir() / f"cffi-wgpu-h-{digest}.json"


def cache_key(csource: str) -> str:
    """What the parse depends on: the header's text and the versions of cffi, pycparser and Python."""
    import cffi

    from wgpurender.wgpu_path.device.parser_on_demand import version

    return f"wgpu.h parse\0cffi {cffi.__version__}\0pycparser {version()}\0{sys.version}\0{csource}"


@contextmanager
def cached_wgpu_header() -> Iterator[None]:
    """Within the block, a ``cdef`` of wgpu.h restores a cached parse (or parses and saves one); pycparser is
    imported only if something parses C text (parser_on_demand.py)."""
    import cffi

    from wgpurender.wgpu_path.device.parser_on_demand import on_demand

    if BACKEND_FFI in sys.modules:
        yield
        return
    with on_demand():
        if not _has_internals(cffi.FFI()):
            yield
            return
        yield from _cdef_replaced(cffi)


def _cdef_replaced(cffi) -> Iterator[None]:
    real = cffi.FFI.cdef

    def cdef(self, csource, override=False, packed=False, pack=None):
        if override or packed or pack is not None or not _is_wgpu_header(csource):
            return real(self, csource, override=override, packed=packed, pack=pack)
        return _cdef_cached(self, csource, real)

    cffi.FFI.cdef = cdef
    try:
        yield
    finally:
        cffi.FFI.cdef = real


def _has_internals(ffi) -> bool:
    parser = getattr(ffi, "_parser", None)
    return parser is not None and all(hasattr(parser, name) for name in (*STATE, "_recomplete")) and \
        hasattr(ffi, "_cdefsources") and hasattr(ffi, "_lock")


def _is_wgpu_header(csource) -> bool:
    return isinstance(csource, str) and "wgpuCreateInstance" in csource


def _cdef_cached(ffi, csource: str, real) -> None:
    from wgpurender.wgpu_path.device.cffi_types import install

    _restore_or_parse(ffi, csource, real)
    install(ffi)  # before wgpu-py's import goes on to declare its first callback (cffi_types.py)


def _restore_or_parse(ffi, csource: str, real) -> None:
    global status
    path, key = cache_file(csource), cache_key(csource)
    state = _load(path, key)
    if state is not None:
        with ffi._lock:
            ffi._cdef_version = object()
            for name in STATE:
                setattr(ffi._parser, name, state[name])
            ffi._cdefsources.append(csource)
        status = "restored"
        return
    real(ffi, csource)
    status = "parsed"
    if not ffi._parser._recomplete and _save(path, key, {name: getattr(ffi._parser, name) for name in STATE}):
        status = "parsed and saved"


def _load(path: Path, key: str) -> dict | None:
    from wgpurender.core.files.cache_entry import read_entry
    from wgpurender.wgpu_path.device import cdef_json

    payload = read_entry(path, key)
    if payload is None:
        return None
    try:
        state = cdef_json.loads(payload)
    except (ValueError, KeyError, TypeError, IndexError, AttributeError):  # a miss: parse instead
        return None
    return state if all(name in state for name in STATE) else None


def _save(path: Path, key: str, state: dict) -> bool:
    from wgpurender.core.files.cache_entry import write_entry
    from wgpurender.wgpu_path.device import cdef_json

    try:
        payload = cdef_json.dumps(state)
    except (cdef_json.Unsupported, ValueError, TypeError):  # a cffi with other internals: parse every time
        return False
    return write_entry(path, key, payload)
