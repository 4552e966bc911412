"""Which native WebGPU the wgpu path runs on: wgpu-native (wgpu-py's own, the default) or Dawn (wgpudawn).

wgpudawn 0.32 (PyPI, ``pip install 'wgpurender[dawn]'``) is wgpu-py's API bound to Google's Dawn in cffi's API
mode, without wgpu-py's poll thread; ``wgpudawn.install_as_wgpu()`` makes ``import wgpu`` return it, so it must
run before anything imports ``wgpu``. Chosen per process with ``$WGPURENDER_BINDING=dawn`` (or the
``wgpu-dawn`` implementation of ``verify --matrix``, a child process with that variable), read when the wgpu
path is first imported (wgpu_path/__init__.py).

What differs on Dawn (gpu.py asks :func:`name`): no wgpu-native instance extras (no backend flags, no
validation switch), no ``immediates`` (the plan then puts material factors in a uniform buffer), and Dawn
refuses Vulkan drivers without ``shaderUniform*ArrayDynamicIndexing`` (lavapipe on Mesa 22.3.6): there
:func:`refusal` is the one line the user sees.

wgpu-native v30 (not yet wrapped by a wgpu-py release, 2026-11) fixes the lock that makes a waiting
``device.poll`` block ``queue.submit`` (gfx-rs/wgpu#9470, fixed by #9475) and makes ``map_async`` flush
pending writes (#9307): the two places where wgpu-native's frame loop costs more than Dawn's today.
"""

from __future__ import annotations

import os
import sys

from wgpurender.core.errors import UserError

BINDING_ENV = "WGPURENDER_BINDING"
BINDINGS = ("wgpu-native", "dawn")
_installed: list[str] = []


def requested() -> str:
    value = os.environ.get(BINDING_ENV, "") or "wgpu-native"
    if value not in BINDINGS:
        raise UserError(f"${BINDING_ENV}={value!r} is not a binding: choose {' or '.join(BINDINGS)}")
    return value


def install() -> str:
    """Install the requested binding as ``wgpu`` (once per process); returns its name."""
    if _installed:
        return _installed[0]
    try:
        want = requested()
    except UserError:  # at import time: the first device request says so, as one line (gpu.py)
        return ""
    if want == "dawn":
        loaded = sys.modules.get("wgpu")
        if loaded is not None and "wgpudawn" not in getattr(loaded, "__name__", "") + str(getattr(loaded, "__file__",
                                                                                                   "")):
            raise UserError(f"${BINDING_ENV}=dawn was set after wgpu-native was loaded in this process: set it "
                            "before starting Python")
        try:
            import wgpudawn
        except ImportError:
            raise UserError(f"${BINDING_ENV}=dawn needs wgpudawn: pip install 'wgpurender[dawn]'") from None
        wgpudawn.install_as_wgpu()
    _installed.append(want)
    return want


def name() -> str:
    """The binding this process runs on."""
    return _installed[0] if _installed else requested()


def refusal(found_backends: list[str]) -> str:
    """The one line for Dawn finding no usable adapter."""
    others = f" (it found only: {', '.join(found_backends)})" if found_backends else ""
    return ("Dawn (wgpudawn) offers no adapter on this machine" + others + ": it refuses Vulkan drivers without "
            "shaderUniform*ArrayDynamicIndexing, such as lavapipe on Mesa 22.3.6; unset $WGPURENDER_BINDING to use "
            "wgpu-native")
