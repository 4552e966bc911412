"""The course stages, found by scanning this package: each module defines one Stage subclass.

Adding a stage is adding a module; nothing else needs to change.
"""

from __future__ import annotations

import functools
import importlib
import pkgutil

from ..errors import UserError
from .base import Stage


@functools.cache
def all_stages() -> dict[str, type[Stage]]:
    """Stage classes by name, in course order."""
    found: list[type[Stage]] = []
    for mod in pkgutil.iter_modules(__path__):
        if mod.name.startswith("_") or mod.name == "base":
            continue
        module = importlib.import_module(f"{__name__}.{mod.name}")
        for obj in vars(module).values():
            if isinstance(obj, type) and issubclass(obj, Stage) and obj.name and obj.__module__ == module.__name__:
                found.append(obj)
    found.sort(key=lambda cls: cls.order)
    return {cls.name: cls for cls in found}


def get_stage(name: str) -> type[Stage]:
    stages = all_stages()
    if name not in stages:
        raise UserError(f"unknown stage {name!r}: valid stages are {', '.join(stages)}")
    return stages[name]
