"""The raw-Vulkan reference path: the course's stages through the `vulkan` binding, from GLSL.

One module per course concept, so that a reader can put each beside its wgpu
counterpart: instance (instance, physical device, queue family, device),
validation (layer + debug messenger), memory (memory types, buffers, staging),
images (images, views, layouts, barriers), commands (pools, command buffers,
fences), descriptors, renderpass (attachments, subpasses, dependencies,
framebuffers), pipeline (layouts, cache, fixed-function state, viewport flip),
glsl (glslc -> SPIR-V -> shader modules), readback (vkCmdCopyImageToBuffer),
stages/ (one module per stage, named like wgpurender/wgpu_path/stages/), and scene/ (scene files: the
final scene in one render pass of two subpasses).

Public API: :func:`render_reference` and :func:`reference_stage_names`.
Importing this package does not touch Vulkan; the first render does.
"""

from __future__ import annotations

import numpy as np

from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY


def render_reference(
    stage: str,
    size: tuple[int, int] | None = (800, 600),
    fmt: str | None = None,
    msaa: int | None = None,
    t: float = 0.0,
    anisotropy: str = DEFAULT_ANISOTROPY,
) -> np.ndarray:
    """Render ``stage`` (or a scene file, ``*.toml``) on the raw-Vulkan path; see
    :func:`wgpurender.raw_path.render.render_reference`."""
    from wgpurender.raw_path.render import render_reference as render

    return render(stage, size=size, fmt=fmt, msaa=msaa, t=t, anisotropy=anisotropy)


def reference_stage_names() -> list[str]:
    """The stages this path can render, in course order."""
    from wgpurender.raw_path.stages import all_ref_stages

    return list(all_ref_stages())
