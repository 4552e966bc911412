"""pycparser imported when cffi first parses C text, not when cffi makes its first FFI (issue 31.5, first pixel).

``cffi.FFI()`` imports ``cffi.cparser``, which imports pycparser (its lexer and parser tables: ~20 ms of the
first pixel on lavapipe's host). With wgpu.h's parse restored from the cache (cdef_cache.py) and C type names
parsed by cffi_types.py's fast path, most processes never parse C text at all. Within :func:`on_demand`, ``import
pycparser`` binds a stand-in module whose first attribute read imports the real package and forwards to it, so
cffi keeps working unchanged the moment it does need a parser. :func:`version` reads pycparser's version from
its ``__init__.py`` without importing it (the cache key needs it). This reaches into import machinery the way
cdef_cache.py and cffi_types.py reach into cffi: tests/test_cdef_cache.py checks the result in fresh processes.
"""

from __future__ import annotations

import importlib
import re
import sys
import types
from collections.abc import Iterator
from contextlib import contextmanager

NAME = "pycparser"


class _StandIn(types.ModuleType):
    """Imports the real pycparser on the first attribute read, then forwards every read to it."""

    def __getattr__(self, attr: str):
        real = _real()
        return getattr(real, attr)


def _real() -> types.ModuleType:
    module = sys.modules.get(NAME)
    if module is None or isinstance(module, _StandIn):
        sys.modules.pop(NAME, None)
        module = importlib.import_module(NAME)
    return module


@contextmanager
def on_demand() -> Iterator[None]:
    """Within the block, ``import pycparser`` (cffi.cparser's) gets the stand-in; nothing if it is imported."""
    if NAME in sys.modules or "cffi.cparser" in sys.modules:
        yield
        return
    stand_in = _StandIn(NAME)
    sys.modules[NAME] = stand_in
    try:
        yield
    finally:
        if sys.modules.get(NAME) is stand_in:
            del sys.modules[NAME]


def version() -> str:
    """pycparser's ``__version__``, read from its source when it is not imported (else the module's)."""
    module = sys.modules.get(NAME)
    if module is not None and not isinstance(module, _StandIn):
        return module.__version__
    from importlib.machinery import PathFinder

    spec = PathFinder.find_spec(NAME)  # on sys.path, past the stand-in in sys.modules
    origin = getattr(spec, "origin", None)
    if origin:
        try:
            with open(origin, encoding="utf-8") as f:
                found = re.search(r"""^__version__\s*=\s*["']([^"']+)["']""", f.read(), re.MULTILINE)
        except OSError:
            found = None
        if found:
            return found.group(1)
    return _real().__version__
