"""Which rows of the Vulkan -> wgpu mapping table (wgpurender/concepts.py) each course step teaches.

A step gets the rows named for it in :data:`STEP_CONCEPTS` (what the course introduces at
that step) plus every row whose code locations are in the step's own modules
(``stages/<module>`` or ``raw_path/stages/<module>``), in the table's order. Code
locations are shown as ``path:line`` from the repository root, found with :mod:`inspect`.
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from pathlib import Path

from wgpurender.concepts import CONCEPTS, Concept, resolve, short

REPO_ROOT = Path(__file__).resolve().parents[2]

# What the course introduces at each step (stage names, and "scene" for every scene file).
STEP_CONCEPTS: dict[str, tuple[str, ...]] = {
    "clear": ("instance", "physical device", "queue families", "device", "images", "layouts and transitions",
              "command pool and buffers", "fences", "offscreen readback"),
    "clear-pass": ("render pass", "framebuffer", "begin info and clear values",
                   "attachment descriptions and references", "views"),
    "triangle": ("pipeline", "pipeline layout", "shader modules and SPIR-V", "input assembly", "viewport and scissor",
                 "rasterizer", "blending", "dynamic state"),
    "triangle-buffers": ("vertex input bindings and attributes", "heaps and memory types", "staging"),
    "offscreen": ("offscreen readback", "barriers with stage and access masks", "subresources"),
    "msaa": ("multisample", "attachment descriptions and references"),
    "msaa-post": ("subpasses and dependencies", "input attachments", "multisample"),
    "3d": ("depth/stencil", "descriptor pool", "set layouts", "sets and updates", "push constants", "UBO alignment"),
    "textured": ("samplers", "mipmaps", "images", "views", "layouts and transitions"),
    "scene": ("subpasses and dependencies", "input attachments", "pipeline cache", "shader modules and SPIR-V",
              "push constants", "surface", "presentation and present modes", "swapchain", "semaphores"),
}


@dataclass(frozen=True)
class Location:
    """One code location: the table's ``module:attr`` text, and ``path:line`` when it could be found."""

    text: str
    where: str


def rows_for(step: str, modules: tuple[str, ...] = ()) -> list[Concept]:
    """The concept rows of ``step``; ``modules``: the step's own modules, e.g. ``("stages.cube3d",)``."""
    names = set(STEP_CONCEPTS.get(step, ()))
    prefixes = tuple(f"wgpurender.{m}:" for m in modules)
    out = []
    for row in CONCEPTS:
        locations = (*row.raw, *row.wgpu_where)
        if row.name in names or (prefixes and any(loc.startswith(prefixes) for loc in locations)):
            out.append(row)
    return out


def locate(location: str) -> Location:
    """``path:line`` of a ``module:attr`` location (the module file alone for constants)."""
    try:
        obj = resolve(location)
        target = inspect.unwrap(obj)
        if isinstance(target, property):
            target = target.fget
        path = Path(inspect.getsourcefile(target) or "")
        try:
            line = inspect.getsourcelines(target)[1]
        except (OSError, TypeError):
            line = None
    except (ImportError, AttributeError, TypeError, ValueError):
        module = location.split(":")[0]
        path, line = Path(*module.split(".")).with_suffix(".py"), None
    try:
        rel = path.resolve().relative_to(REPO_ROOT)
    except ValueError:
        rel = path
    return Location(short(location), f"{rel}:{line}" if line else str(rel))
