"""$XDG_RUNTIME_DIR for the drivers: a private folder when the user's is unset or invalid.

Creating a Vulkan instance (wgpu-native's or the raw path's) makes Mesa's Wayland window-system support call
libwayland's ``wl_display_connect``, which prints "error: XDG_RUNTIME_DIR is invalid or not set in the
environment." on stderr, once per try, when the variable is unset or not an absolute path: four lines before
every command's output over SSH as root, in containers, CI and notebooks. The variable only says where per-user
sockets live (the Wayland compositor's among them); an empty private folder means "no compositor here", which is
what an unset variable means too, without the noise. A valid value (a desktop session's) is never changed.

The folder is made with mode 0700 (as the XDG Base Directory spec asks of this directory) and removed when the
process ends. API-free: called by both paths before they create their instance.
"""

from __future__ import annotations

import atexit
import os
import shutil
import tempfile

RUNTIME_ENV = "XDG_RUNTIME_DIR"


def runtime_dir_valid(value: str | None) -> bool:
    """What libwayland accepts (set, absolute), and a folder that exists, so sockets could be found there."""
    return bool(value) and os.path.isabs(value) and os.path.isdir(value)


def ensure_runtime_dir() -> str:
    """Set $XDG_RUNTIME_DIR to a private 0700 folder when it is unset or invalid; return the value in effect."""
    current = os.environ.get(RUNTIME_ENV)
    if runtime_dir_valid(current):
        return current
    private = tempfile.mkdtemp(prefix="wgpurender-runtime-")  # mode 0700
    atexit.register(shutil.rmtree, private, True)
    os.environ[RUNTIME_ENV] = private  # os.environ writes through to the C environment the drivers read
    return private
