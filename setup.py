"""Build hook: ship shaders_wgsl/ and shaders_glsl/ inside the wheel.

The shader folders stay at the repository's top level (the course's layout: a reader
finds the WGSL and the GLSL beside each other, not deep in the package). setuptools'
package-data can only reach files inside a package, so ``build_py`` copies both folders
into ``wgpurender/_shaders/{wgsl,glsl}`` of the build tree; the installed package reads
them from there through importlib.resources (wgpurender/wgpu_path/shaders.py, raw_path/glsl.py).
An editable install (``pip install -e``) builds nothing: it reads the checkout's folders.
Everything else is declared in pyproject.toml.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent
SHADER_FOLDERS = {"shaders_wgsl": "wgsl", "shaders_glsl": "glsl"}  # repository folder -> wgpurender/_shaders/<name>


class BuildPyWithShaders(build_py):
    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):
            return
        for folder, name in SHADER_FOLDERS.items():
            source = HERE / folder
            if not source.is_dir():
                raise RuntimeError(f"{source} is missing: the wheel would ship without its shaders")
            dest = Path(self.build_lib) / "wgpurender" / "_shaders" / name
            shutil.rmtree(dest, ignore_errors=True)
            shutil.copytree(source, dest)


setup(cmdclass={"build_py": BuildPyWithShaders})
