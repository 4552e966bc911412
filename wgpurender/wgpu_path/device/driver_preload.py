"""Load the Vulkan drivers' libraries on a thread at the very start, before wgpu-py is imported (issue 31.5).

Making the device (context.start_context) can only begin once wgpu-py and its backend are imported: ~0.1 s of
Python on the main thread. The first thing the Vulkan loader does inside it is ``dlopen`` every driver its
manifests list, and a driver library is large (lavapipe links LLVM: 55-75 ms to load here; NVIDIA's is
libGLX_nvidia with its compiler libraries). :func:`start` does those ``dlopen`` calls on a thread while the
main thread imports (ctypes releases the GIL around ``dlopen``), so the loader later finds them loaded. Nothing
else changes: the same libraries, loaded the same way (``RTLD_LOCAL``), the loader's own checks and errors
after; a library that fails to load here is left for the loader to report.

Which libraries: what the loader would load (its LoaderInterfaceArchitecture.md): the manifests named by
``$VK_DRIVER_FILES`` (or the older ``$VK_ICD_FILENAMES``) and ``$VK_ADD_DRIVER_FILES`` (files or folders), else
the ``vulkan/icd.d`` folders of the XDG config and data directories and ``/etc``. With the loader's driver
filters set (``$VK_LOADER_DRIVERS_SELECT`` / ``_DISABLE``) nothing is preloaded: which drivers those leave is
the loader's to decide.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

BACKEND_ENV = "WGPURENDER_BACKEND"  # the backend a process asks for (context.requested_backend reads it too)
LOADER = "libvulkan.so.1"  # what wgpu-native opens
FILTERS = ("VK_LOADER_DRIVERS_SELECT", "VK_LOADER_DRIVERS_DISABLE")
_started: list[threading.Thread] = []
_loaded: list[object] = []  # the handles, kept: a library is never closed


def wants_vulkan(backend: str | None, env: dict[str, str] | None = None) -> bool:
    """Whether the request (the argument, else $WGPURENDER_BACKEND, else Vulkan) may use the Vulkan drivers."""
    env = os.environ if env is None else env
    return (backend or env.get(BACKEND_ENV) or "vulkan").lower() in ("vulkan", "auto")


def manifests(env: dict[str, str] | None = None) -> list[Path]:
    """The driver manifests the Vulkan loader reads, in its order (files, and the .json files of folders)."""
    env = os.environ if env is None else env
    named = env.get("VK_DRIVER_FILES") or env.get("VK_ICD_FILENAMES")
    places = [*_split(named), *_split(env.get("VK_ADD_DRIVER_FILES"))] if named else [
        *_split(env.get("VK_ADD_DRIVER_FILES")), *_search_folders(env)]
    out: list[Path] = []
    for place in places:
        found = sorted(place.glob("*.json")) if place.is_dir() else [place] if place.is_file() else []
        out += [p for p in found if p not in out]
    return out


def _split(value: str | None) -> list[Path]:
    return [Path(v) for v in (value or "").split(os.pathsep) if v]


def _search_folders(env: dict[str, str]) -> list[Path]:
    home = Path(env.get("HOME", "/"))
    config = [env.get("XDG_CONFIG_HOME") or str(home / ".config"),
              *(env.get("XDG_CONFIG_DIRS") or "/etc/xdg").split(":"), "/usr/local/etc", "/etc"]
    data = [env.get("XDG_DATA_HOME") or str(home / ".local/share"),
            *(env.get("XDG_DATA_DIRS") or "/usr/local/share:/usr/share").split(":")]
    return [Path(d) / "vulkan" / "icd.d" for d in [*config, *data] if d]


def library(manifest: Path) -> str | None:
    """A manifest's driver library as ``dlopen`` takes it: a bare name as written, a relative path from the
    manifest's folder; None for a manifest that cannot be read or names none."""
    import json  # here, on the thread: ~2 ms the main thread does not wait for

    try:
        name = json.loads(manifest.read_text())["ICD"]["library_path"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if not isinstance(name, str) or not name:
        return None
    return name if "/" not in name or name.startswith("/") else str(manifest.parent / name)


def libraries(env: dict[str, str] | None = None) -> list[str]:
    """The loader, then each driver library the manifests name (once each); none with the loader's filters."""
    env = os.environ if env is None else env
    if any(env.get(f) for f in FILTERS):
        return []
    found = [lib for lib in map(library, manifests(env)) if lib]
    return [LOADER, *dict.fromkeys(found)]


def start(backend: str | None = None) -> None:
    """Begin loading the drivers on a daemon thread (once per process); nothing for a non-Vulkan request."""
    if _started or not wants_vulkan(backend):
        return
    thread = threading.Thread(target=_load, name="wgpurender-driver-preload", daemon=True)
    _started.append(thread)
    thread.start()


def _load() -> None:
    import ctypes

    for name in libraries():
        try:
            _loaded.append(ctypes.CDLL(name))
        except OSError:  # the loader will say what is wrong with it, or skip it as it would anyway
            pass


def join() -> None:
    """Wait for the thread (tests; a process need not: the loader's own ``dlopen`` waits for it)."""
    for thread in _started:
        thread.join()
