"""Every reach into wgpu-py's private parts, in one module, with the version it was written against.

wgpu-py 0.32 has no public way to do four things the course needs, so the project reaches past its API:

1. **the native library** (``wgpu.backends.wgpu_native._ffi``: ``ffi`` and ``lib``) and the handles behind
   wgpu-py's objects (``._internal``, a canvas context's ``._surface_id``): clear_texture, the timestamp period,
   the surface's real capabilities (native.py);
2. **the cffi parse of wgpu.h** made when that module is imported: cached per machine (cdef_cache.py) and its
   type parser sped up (cffi_types.py), both keyed on :data:`BACKEND_FFI`;
3. **the device's poll thread** (``device._poller``, ``device._poll_wait``, a promise's ``_state``): a readback
   maps on the caller's thread instead of handing the wait to that thread (gpu.py, facts.md);
4. **the module path** of the backend itself (``wgpu.backends.wgpu_native``) for the above.

A new wgpu-py may move any of them: :func:`version_note` says in one line what to do, and
tests/test_wgpu_private.py checks each reach on the installed wgpu-py.
"""

from __future__ import annotations

import sys
from contextlib import contextmanager

WRITTEN_FOR = "0.32."
BACKEND_FFI = "wgpu.backends.wgpu_native._ffi"


def version_note(version: str | None = None) -> str:
    """"" for the wgpu-py these reaches were written for, else the one line that says what to do."""
    version = version or _installed_version()
    if version.startswith(WRITTEN_FOR):
        return ""
    return (f"wgpurender reaches into wgpu-py {WRITTEN_FOR}x's private parts and wgpu-py {version} is installed: "
            f"pip install 'wgpu=={WRITTEN_FOR}*', or update wgpurender/wgpu_path/device/wgpu_private.py until "
            "tests/test_wgpu_private.py passes")


def _installed_version() -> str:
    """wgpu-py's version: the loaded module's (importing wgpu loads no backend: cdef_cache.py still comes first),
    else the package metadata's (importing importlib.metadata and reading it cost ~15 ms of the first pixel)."""
    loaded = getattr(sys.modules.get("wgpu"), "__version__", None)
    if isinstance(loaded, str):
        return loaded
    from importlib import metadata

    return metadata.version("wgpu")


def native():
    """(ffi, lib) of wgpu-native as wgpu-py loaded it."""
    from wgpu.backends.wgpu_native._ffi import ffi, lib

    return ffi, lib


def handle(obj):
    """The native handle (a cffi pointer) behind a wgpu-py object: device, queue, adapter, texture, encoder."""
    return obj._internal


def surface_handle(context):
    """The WGPUSurface behind a canvas context; None before it is made."""
    return getattr(context, "_surface_id", None)


def poller(device):
    """The device's poll thread object (wgpu-py 0.32), or None where this wgpu-py has none."""
    return getattr(device, "_poller", None) if hasattr(device, "_poll_wait") else None


@contextmanager
def poller_replaced(device, stand_in):
    """``device._poller`` is ``stand_in`` within the block."""
    real = device._poller
    device._poller = stand_in
    try:
        yield real
    finally:
        device._poller = real


def poll_wait(device) -> None:
    """One blocking wgpuDevicePoll on this thread."""
    device._poll_wait()


def pending(promise) -> bool:
    """Whether a wgpu-py promise has not resolved yet."""
    return getattr(promise, "_state", "") == "pending"
