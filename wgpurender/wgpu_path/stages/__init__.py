"""The course stages, found by scanning this package: each module defines one Stage subclass.

Adding a stage is adding a module (and its row in the course's order table,
wgpurender/core/course/steps.py, which places it; without one it is listed last).
Nothing imports a stage module except this registry, the runners, the CLI, the
bench and tests (docs/architecture.md).
"""

from __future__ import annotations

import functools

from wgpurender.core.course.discovery import subclasses_in_package
from wgpurender.core.errors import UserError
from wgpurender.core.files.assets import unknown_target
from wgpurender.wgpu_path.stages.base import Stage


@functools.cache
def all_stages() -> dict[str, type[Stage]]:
    """Stage classes by name, in course order."""
    return {cls.name: cls for cls in subclasses_in_package(__path__, __name__, Stage)}


def get_stage(name: str) -> type[Stage]:
    stages = all_stages()
    if name not in stages:
        raise UserError(f"unknown stage {name!r}: {unknown_target(name, list(stages))}")
    return stages[name]
