"""What a GL adapter's version string says about what wgpu 29 can do on it (wgpu-py exposes no downlevel flags).

wgpu's GL backend (wgpu-hal ``gles``) writes every shader through naga's GLSL backend for the context's own GLSL
version, while it reads the context's abilities from its extensions: a desktop GL 3.3 context with
GL_ARB_shader_storage_buffer_object and GL_ARB_compute_shader (NVIDIA's EGL, driver 580: "3.3.0 NVIDIA 580.159.04",
measured on the H100, docs/perf-h100/2026-11-27-glinst) gets limits that claim storage buffers and compute, which
naga then cannot write. The plan reads these facts through :meth:`~wgpurender.core.plan.model.AdapterFacts.of`; the
wgpu path refuses a context it would bind wrongly (wgpu_path/device/context.refuse_broken_gl).
"""

from __future__ import annotations

import re

# naga's GLSL output needs these versions (naga/src/back/glsl/features.rs): storage buffers 4.00 (ES 3.10), compute
# 4.30 (ES 3.10). wgpu-hal takes a GL 3.3 context with the ARB extensions as having both, and NVIDIA's EGL gives
# exactly the 3.3 it asks for ("3.3.0 NVIDIA 580.159.04", measured on the H100, docs/perf-h100/2026-11-27-glinst).
GLSL_NEEDS = {"storage": (400, 310), "compute": (430, 310)}


def glsl_version(gl_version: str) -> tuple[bool, int] | None:
    """(ES?, GLSL version as naga numbers it) from a GL adapter's version string, e.g. "3.3.0 NVIDIA 580" ->
    (False, 330), "OpenGL ES 3.2 Mesa" -> (True, 320); None when it names no version."""
    found = re.search(r"(OpenGL ES )?(\d+)\.(\d)", gl_version)
    if found is None:
        return None
    return bool(found.group(1)), int(found.group(2)) * 100 + int(found.group(3)) * 10


def glsl_allows(what: str, gl_version: str) -> bool:
    """Whether naga can write ``what`` ("storage" or "compute") for a GL context of this version string."""
    version = glsl_version(gl_version)
    if version is None:
        return True
    es, number = version
    return number >= GLSL_NEEDS[what][es]


CANNOT_DRAW = "cannot draw correctly"  # the refusal's words: written by the device layer, matched by verify's probe


def gl_binding_fault(gl_version: str, compute_invocations: int) -> str:
    """Why wgpu 29 cannot bind resources on this GL context ("" when it can): it trusts the shaders' own
    ``layout(binding = N)`` once compute is supported (wgpu-hal's SHADER_BINDING_LAYOUT), which a desktop context
    below 4.2 supports only through GL_ARB_compute_shader, while naga writes no binding qualifiers below GLSL 420:
    every uniform block and texture is then bound at 0, a wrong image with no error (NVIDIA's EGL, GL 3.3: docs/
    backends.md, "Instance data on OpenGL")."""
    version = glsl_version(gl_version)
    if version is None or version[0] or version[1] >= 420 or compute_invocations <= 0:
        return ""
    return (f"a GL {version[1] // 100}.{version[1] // 10 % 10} context with compute shaders (GL_ARB_compute_shader): "
            "wgpu-py 0.32's GL backend then binds every uniform block and texture at slot 0 (its shaders get no "
            "binding qualifiers below GLSL 4.20), which draws wrong images")
