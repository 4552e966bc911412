"""Build hook: ship the shaders, the course's assets and its notebook inside the wheel.

The shader folders, ``assets/`` and ``examples/`` stay at the repository's top level (the course's
layout: a reader finds the WGSL and the GLSL beside each other, the scenes and models beside the
code, not deep in the package). setuptools' package-data can only reach files inside a package, so
``build_py`` copies them into the build tree: ``wgpurender/_shaders/{wgsl,glsl}``, ``wgpurender/_assets``,
``wgpurender/_examples``; the installed
package reads them from there through importlib.resources (wgpurender/core/shaders/shader_files.py,
wgpurender/core/files/assets.py). An editable install (``pip install -e``)
builds nothing: it reads the checkout's folders. Everything else is declared in pyproject.toml.

The raw path's SPIR-V ships too: every variant in ``shaders_glsl/variants.txt`` is compiled with glslc into
``wgpurender/_shaders/spirv`` under the name wgpurender/core/shaders/spirv_names.py gives it (a hash of its GLSL
source, flags and defines), so a pip-installed user needs no glslc. Building the wheel needs glslc (or
WGPURENDER_WHEEL_NO_SPIRV=1 for a wheel whose raw path needs glslc at run time).
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
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
        if not os.environ.get("WGPURENDER_WHEEL_NO_SPIRV"):
            compile_spirv(Path(self.build_lib) / "wgpurender" / "_shaders" / "spirv")


def _spirv_names():
    """wgpurender/core/shaders/spirv_names.py loaded by its path (the package is not importable while it builds)."""
    spec = importlib.util.spec_from_file_location("spirv_names", HERE / "wgpurender" / "core" / "shaders" /
                                                  "spirv_names.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def compile_spirv(dest: Path) -> None:
    """glslc every variant of shaders_glsl/variants.txt into ``dest``, named as the raw path looks them up."""
    names = _spirv_names()
    glslc = shutil.which("glslc")
    if glslc is None:
        raise RuntimeError("glslc is needed to build the wheel (it ships the raw path's SPIR-V): apt install glslc, "
                           "or set WGPURENDER_WHEEL_NO_SPIRV=1 for a wheel that needs glslc at run time")
    shutil.rmtree(dest, ignore_errors=True)
    dest.mkdir(parents=True)
    glsl = HERE / "shaders_glsl"
    for file_name, defines in names.read_variants((glsl / names.VARIANTS_FILE).read_text()):
        source = glsl / file_name
        out = dest / names.spirv_name(file_name, source.read_bytes() + names.included(source), defines)
        subprocess.run([glslc, *names.glslc_args(defines), str(source), "-o", str(out)], check=True)


setup(cmdclass={"build_py": BuildPyWithCourseData})
