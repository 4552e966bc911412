"""The raw-Vulkan versions of the course stages, one module each, named like wgpurender/wgpu_path/stages/.

Found by scanning this package, like the wgpu stages: a module defines one
:class:`RefStage` subclass whose ``name`` matches the wgpu stage it mirrors
(plus stages only this path has so far, e.g. msaa-post), listed in the course's
order (wgpurender/core/course/steps.py).
"""

from __future__ import annotations

import functools

from wgpurender.core.course.discovery import subclasses_in_package
from wgpurender.core.errors import UserError
from wgpurender.core.files.assets import unknown_target
from wgpurender.raw_path.stages.base import RefStage


@functools.cache
def all_ref_stages() -> dict[str, type[RefStage]]:
    """Stage classes by name, in course order."""
    return {cls.name: cls for cls in subclasses_in_package(__path__, __name__, RefStage)}


def get_ref_stage(name: str) -> type[RefStage]:
    stages = all_ref_stages()
    if name not in stages:
        raise UserError(f"unknown stage {name!r} for the raw-Vulkan reference path: "
                        f"{unknown_target(name, list(stages))}")
    return stages[name]
