"""Where the shader source folders are: in the installed package, in the checkout, or where an env var says.

The repository keeps its shaders at the top level (``shaders_wgsl/``, ``shaders_glsl/``), beside the
package rather than inside it. A wheel carries copies in ``wgpurender/_shaders/{wgsl,glsl}`` (setup.py's
build hook puts them there), read through :mod:`importlib.resources`; an editable install or a plain
checkout has no copies and reads the top-level folders. An environment variable overrides both.

API-free (no wgpu, no vulkan): the wgpu path (``shaders.py``) and the raw path (``raw_path/device/shaders.py``)
each call it for their own folder.
"""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path

# kind -> (folder in the repository, folder inside the installed package)
FOLDERS = {"wgsl": "shaders_wgsl", "glsl": "shaders_glsl"}


def packaged_folder(kind: str) -> Path | None:
    """``wgpurender/_shaders/<kind>`` of an installed wheel, when it exists."""
    try:
        folder = resources.files("wgpurender") / "_shaders" / kind
    except ModuleNotFoundError:  # pragma: no cover - the package is importing itself
        return None
    path = Path(str(folder))
    return path if path.is_dir() else None


def checkout_folder(kind: str) -> Path:
    """The repository's top-level folder (an editable install or a source checkout)."""
    return Path(__file__).resolve().parents[3] / FOLDERS[kind]


def shader_folder(kind: str, env_var: str) -> Path:
    """The folder to read ``kind`` shaders from: ``$env_var``, else the wheel's copy, else the checkout's."""
    override = os.environ.get(env_var)
    if override:
        return Path(override)
    return packaged_folder(kind) or checkout_folder(kind)
