"""Shader modules from GLSL: shaders_glsl/<name> compiled to SPIR-V by glslc, cached on disk.

The course compiles its shaders offline with glslc (shaderc) and hands the SPIR-V
words to vkCreateShaderModule. We do the same at run time and keep the result in
~/.cache/wgpurender/spirv/, keyed by a hash of the source and the compiler flags,
so that glslc runs once per shader edit (and is not needed at all on a warm cache). Each file is a verified
cache entry (core/files/cache_entry.py): empty, truncated, altered or written for another source is a miss and
glslc runs again. The key leaves out glslc's version: SPIR-V is portable, and any glslc's output for the same
source and flags is a valid module of the same shader.
A wheel ships the SPIR-V of the bundled course's variants (``wgpurender/_shaders/spirv``, compiled by setup.py
under the same names, core/shaders/spirv_names.py): used when its name (a hash of this very source, the flags
and the defines) matches, so a pip-installed user needs no glslc for the course.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import vulkan as vk

from wgpurender.core.errors import UserError
from wgpurender.core.files.cache_entry import cache_folder, read_entry, write_entry
from wgpurender.core.shaders.shader_files import packaged_folder, shader_folder
from wgpurender.core.shaders.spirv_names import GLSLC_ARGS, glslc_args, spirv_key, spirv_name
from wgpurender.core.shaders.spirv_names import included as _included

GLSL_DIR_ENV = "WGPURENDER_GLSL"
# glslc reports "path:LINE: error: message"
_ERROR_LINE = re.compile(r"^(?P<file>.*?):(?P<line>\d+): error: (?P<msg>.*)$", re.MULTILINE)


def glsl_dir() -> Path:
    """The GLSL folder: $WGPURENDER_GLSL, else the wheel's copy of shaders_glsl/, else the checkout's."""
    return shader_folder("glsl", GLSL_DIR_ENV)


def cache_dir() -> Path:
    """SPIR-V cache in the user's cache folder (never the install folder, which may be read-only)."""
    return cache_folder("spirv")


def glsl_path(name: str) -> Path:
    path = glsl_dir() / name
    if not path.is_file():
        raise UserError(f"GLSL shader {name} not found in {glsl_dir()} "
                        f"(set ${GLSL_DIR_ENV} to the shaders_glsl folder)")
    return path


def compile_glsl(path: str | os.PathLike, defines: tuple[str, ...] = ()) -> bytes:
    """SPIR-V for a .vert/.frag file: from the cache, else from glslc (then cached).

    ``defines``: preprocessor definitions passed as ``-D`` flags (``"ALBEDO_MAP"``, ``"POINT_LIGHTS=2"``),
    for shaders with variants; they are part of the cache key.
    """
    path = Path(path)
    source = path.read_bytes() + _included(path)
    args = glslc_args(defines)
    key = spirv_key(path.name, source, defines)
    cached = cache_dir() / spirv_name(path.name, source, defines)
    if cached.name in _MEMORY_CACHE:
        return _MEMORY_CACHE[cached.name]
    shipped = packaged_folder("spirv")
    if shipped is not None and (shipped / cached.name).is_file():  # the wheel's, made from this very source
        spirv = (shipped / cached.name).read_bytes()
        if is_spirv(spirv):
            return spirv
    spirv = read_entry(cached, key)
    if spirv is not None and is_spirv(spirv):
        return spirv
    spirv = _run_glslc(path, args)
    if not write_entry(cached, key, spirv):  # not writable (read-only home, $XDG_CACHE_HOME a file)
        _MEMORY_CACHE[cached.name] = spirv
    return spirv


def is_spirv(data: bytes) -> bool:
    """A SPIR-V module's shape: whole 32-bit words, the magic number first (the hashes already vouch for it)."""
    return len(data) >= 20 and len(data) % 4 == 0 and data[:4] == b"\x03\x02\x23\x07"


_MEMORY_CACHE: dict[str, bytes] = {}  # where SPIR-V goes when the cache folder is not writable


def _run_glslc(path: Path, args: tuple[str, ...] = GLSLC_ARGS) -> bytes:
    glslc = shutil.which("glslc")
    if glslc is None:
        raise UserError(f"glslc not found on PATH: the raw-Vulkan path compiles GLSL with it, and {path.name} "
                        f"{' '.join(args[len(GLSLC_ARGS):])} is not among the SPIR-V a wheel ships for the bundled "
                        "course (apt install glslc, or the Vulkan SDK)")
    proc = subprocess.run([glslc, *args, str(path), "-o", "-"], capture_output=True)
    if proc.returncode != 0:
        raise UserError(_describe_error(path, proc.stderr.decode(errors="replace")))
    return proc.stdout


def _describe_error(path: Path, stderr: str) -> str:
    match = _ERROR_LINE.search(stderr)
    if match is None:
        first = (stderr.strip().splitlines() or ["glslc failed"])[0]
        return f"GLSL shader {path} failed to compile: {first}"
    return f"GLSL shader {path} line {match['line']}: {match['msg'].strip()}"


def create_shader_module(device, name: str, defines: tuple[str, ...] = ()):
    """vkCreateShaderModule from shaders_glsl/<name>: the create info takes the SPIR-V words (codeSize in bytes)."""
    spirv = compile_glsl(glsl_path(name), defines)
    info = vk.VkShaderModuleCreateInfo(codeSize=len(spirv), pCode=spirv)
    return vk.vkCreateShaderModule(device, info, None)
