"""SPIR-V file names: one GLSL file with its ``-D`` defines, compiled by glslc, is named by a hash of what made it.

The raw path compiles GLSL with glslc and caches the SPIR-V (raw_path/device/shaders.py); a wheel ships the SPIR-V of
every variant the bundled course uses (``shaders_glsl/variants.txt``), compiled when the wheel is built (setup.py loads
this file by its path: it imports nothing of the package), so a pip-installed user needs no glslc. The name's hash
covers the GLSL source bytes, glslc's flags and the defines: a shipped file is used only for the very source it
came from (an edited shader, e.g. through $WGPURENDER_GLSL, no longer matches and is compiled). API-free, stdlib.
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path

# 1.1: the negative viewport height is core there (raw_path/device/pipeline.py)
GLSLC_ARGS = ("--target-env=vulkan1.1",)
VARIANTS_FILE = "variants.txt"  # in shaders_glsl/: "FILE [DEFINE ...]" per line, '#' comments


_INCLUDE = re.compile(rb'^[ \t]*#[ \t]*include[ \t]+"([^"]+)"', re.MULTILINE)


def included(path: Path) -> bytes:
    """The bytes of the files ``path`` includes (``#include "name"``, beside it; one level: shaders_glsl's
    included files include nothing), so that editing an included file changes the key (a shader's key source is
    its own bytes followed by these)."""
    parts = []
    for name in _INCLUDE.findall(path.read_bytes()):
        other = path.parent / name.decode("utf-8", "replace")
        parts.append(other.read_bytes() if other.is_file() else b"")
    return b"\0".join(parts)


def glslc_args(defines: tuple[str, ...] = ()) -> tuple[str, ...]:
    return (*GLSLC_ARGS, *(f"-D{d}" for d in defines))


def spirv_key(file_name: str, source: bytes, defines: tuple[str, ...] = ()) -> bytes:
    """Everything the SPIR-V depends on: the stage (by suffix), glslc's flags with the defines, the GLSL source."""
    parts = [b"spirv", Path(file_name).suffix.encode(), *(a.encode() for a in glslc_args(defines)), source]
    return b"\0".join(parts)


def spirv_name(file_name: str, source: bytes, defines: tuple[str, ...] = ()) -> str:
    """``scene-frag-<24 hex>.spv`` for ``scene.frag`` compiled from ``source`` with ``defines``."""
    path = Path(file_name)
    digest = hashlib.sha256(spirv_key(file_name, source, defines)).hexdigest()
    return f"{path.stem}{path.suffix.replace('.', '-')}-{digest[:24]}.spv"


def read_variants(text: str) -> list[tuple[str, tuple[str, ...]]]:
    """(GLSL file, defines) per line of variants.txt."""
    out = []
    for line in text.splitlines():
        words = line.split("#", 1)[0].split()
        if words:
            out.append((words[0], tuple(words[1:])))
    return out
