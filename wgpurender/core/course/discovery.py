"""Plugins by package scan: every module of a package that defines a subclass of a base.

The wgpu stages and their raw-Vulkan twins are both found this way, so adding one is
adding a module.
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Iterable

from wgpurender.core.course.steps import course_position


def subclasses_in_package(package_path: Iterable[str], package_name: str, base: type) -> list[type]:
    """Named subclasses of ``base`` defined in the package's modules (not imported ones), in course order
    (:mod:`wgpurender.core.course.steps`)."""
    found: list[type] = []
    for mod in pkgutil.iter_modules(package_path):
        if mod.name.startswith("_") or mod.name == "base":
            continue
        module = importlib.import_module(f"{package_name}.{mod.name}")
        for obj in vars(module).values():
            if isinstance(obj, type) and issubclass(obj, base) and obj.name and obj.__module__ == module.__name__:
                found.append(obj)
    return sorted(found, key=lambda cls: course_position(cls.name))
