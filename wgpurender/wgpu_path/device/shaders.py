"""WGSL shaders live as files in shaders_wgsl/ and are loaded by name (the wheel ships them: shader_files.py).

Compiling one is the analogue of vkCreateShaderModule; wgpu takes WGSL text (or
SPIR-V) and translates it for the backend through naga.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import wgpu

from wgpurender.core.errors import UserError
from wgpurender.core.shaders.shader_files import shader_folder

SHADER_DIR_ENV = "WGPURENDER_SHADERS"
_recorders: list[set[Path]] = []  # open recording_loads() blocks


def shader_dir() -> Path:
    """The WGSL folder: $WGPURENDER_SHADERS, else the wheel's copy of shaders_wgsl/, else the checkout's."""
    return shader_folder("wgsl", SHADER_DIR_ENV)


def load_wgsl(name: str) -> str:
    path = shader_dir() / name
    if not path.is_file():
        raise UserError(f"shader {name} not found in {shader_dir()} (set ${SHADER_DIR_ENV} to the shaders_wgsl folder)")
    for loaded in _recorders:
        loaded.add(path.resolve())
    return path.read_text(encoding="utf-8")


@contextmanager
def recording_loads() -> Iterator[set[Path]]:
    """The WGSL files loaded inside the block (the demo window watches them for live reload)."""
    loaded: set[Path] = set()
    _recorders.append(loaded)
    try:
        yield loaded
    finally:
        _recorders.remove(loaded)


def create_shader_module(device: wgpu.GPUDevice, name: str, code: str | None = None) -> wgpu.GPUShaderModule:
    """Compile shaders_wgsl/<name> (or ``code`` generated from it) with a readable error.

    naga reports errors with line and column; we keep that text and name the file.
    """
    source = load_wgsl(name) if code is None else code
    try:
        return device.create_shader_module(label=name, code=source)
    except wgpu.GPUError as err:
        detail = str(err).strip()
        raise UserError(f"shader {name} failed to compile:\n{detail}") from None
