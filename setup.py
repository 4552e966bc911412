"""Build hook: ship the shaders, the course's assets and its notebook inside the wheel.

The shader folders, ``assets/`` and ``examples/`` stay at the repository's top level (the course's
layout: a reader finds the WGSL and the GLSL beside each other, the scenes and models beside the
code, not deep in the package). setuptools' package-data can only reach files inside a package, so
``build_py`` copies them into the build tree: ``wgpurender/_shaders/{wgsl,glsl}``, ``wgpurender/_assets``,
``wgpurender/_examples``; the installed
package reads them from there through importlib.resources (wgpurender/core/shaders/shader_files.py,
wgpurender/core/files/assets.py). An editable install (``pip install -e``)
builds nothing: it reads the checkout's folders. Everything else is declared in pyproject.toml.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent
# repository folder -> folder inside the built wgpurender package
COPIED_FOLDERS = {"shaders_wgsl": "_shaders/wgsl", "shaders_glsl": "_shaders/glsl", "assets": "_assets",
                  "examples": "_examples"}
LEFT_OUT = shutil.ignore_patterns("__pycache__", "*.pyc", ".ipynb_checkpoints", "make_assets.py")


class BuildPyWithCourseData(build_py):
    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):
            return
        for folder, name in COPIED_FOLDERS.items():
            source = HERE / folder
            if not source.is_dir():
                raise RuntimeError(f"{source} is missing: the wheel would ship without it")
            dest = Path(self.build_lib) / "wgpurender" / name
            shutil.rmtree(dest, ignore_errors=True)
            shutil.copytree(source, dest, ignore=LEFT_OUT)


setup(cmdclass={"build_py": BuildPyWithCourseData})
