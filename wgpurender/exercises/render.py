"""Render a stage given as a file (a learner's, a starter, a mistake variant) the way its step is checked.

The learner's file is a module that defines one subclass of the path's stage base class (docs/exercises.md):
``wgpurender.wgpu_path.stages.base.Stage`` or ``wgpurender.raw_path.stages.base.RefStage``, named like the step's
stage. It is rendered headless at the committed references' size, once per time of the step, in the stage's
default format and sample count, and returned as 8-bit RGBA (what the references store).
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import shutil
import sys
import tempfile
from pathlib import Path
from types import ModuleType

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import to_uint8
from wgpurender.exercises.catalogue import Exercise
from wgpurender.exercises.source import course_step

CHECK_SIZE = (256, 192)  # the committed stage references' size (raw_path/make_references.REFERENCE_SIZE)
SCENE_CHECK_SIZE = (320, 240)  # the committed scene references' size (make_references.SCENE_REFERENCE_SIZE)


class StageFileError(Exception):
    """The learner's file does not provide what a stage must (a verdict, not a bug of ours)."""


def base_class(path: str) -> type:
    if path == "wgpu":
        from wgpurender.wgpu_path.stages.base import Stage

        return Stage
    from wgpurender.raw_path.stages.base import RefStage

    return RefStage


def load_module(file: Path) -> ModuleType:
    """Import ``file`` as a module of its own (a unique name, so two files never share one)."""
    digest = hashlib.sha1(str(file.resolve()).encode()).hexdigest()[:12]
    name = f"wgpurender_exercise_{digest}"
    spec = importlib.util.spec_from_file_location(name, file)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def stage_class(module: ModuleType, ex: Exercise) -> type:
    """The one stage class the module defines, checked against the step."""
    base = base_class(ex.path)
    found = [obj for obj in vars(module).values()
             if isinstance(obj, type) and issubclass(obj, base) and obj.__module__ == module.__name__]
    want = course_step(ex.step).stage
    if len(found) != 1:
        names = ", ".join(cls.__name__ for cls in found) or "none"
        raise StageFileError(f"the file must define exactly one subclass of {base.__module__}.{base.__name__} "
                             f"(found {names})")
    if found[0].name != want:
        raise StageFileError(f"{found[0].__name__}.name is {found[0].name!r}: step {ex.step}'s stage is named "
                             f"{want!r}")
    return returns_nothing(found[0], inherited=found[0].record is base.record)


def returns_nothing(cls: type, inherited: bool = False) -> type:
    """``cls`` whose ``record`` is checked to return None (it records commands; a value returned is a
    misunderstanding of the interface, said as one). ``inherited``: the class has no record of its own (the
    base's only raises NotImplementedError), said when the frame is recorded, after setup's own errors."""
    record = cls.record

    def checked_record(self, *args, **kwargs) -> None:
        if inherited:
            raise StageFileError(f"{cls.__name__} has no record method: define record(self, ...) as the starter "
                                 "has it (a misspelt name?)")
        result = record(self, *args, **kwargs)
        if result is not None:
            raise StageFileError(f"{cls.__name__}.record returned a {type(result).__name__}: it records the frame's "
                                 "commands and returns nothing (docs/exercises.md)")

    return type(cls.__name__, (cls,), {"record": checked_record, "__module__": cls.__module__})


def render_class(cls: type, ex: Exercise) -> list[np.ndarray]:
    """The stage's images at the step's times, 8-bit RGBA."""
    if ex.path == "wgpu":
        from wgpurender.wgpu_path.device.context import get_context
        from wgpurender.wgpu_path.render import render_stage_class

        frames = render_stage_class(cls, CHECK_SIZE, None, None, ex.times, get_context("Vulkan"))
        images = [frame.pixels for frame in frames]
    else:
        from wgpurender.raw_path.render import render_stage_class

        images = [render_stage_class(cls, CHECK_SIZE, t=t) for t in ex.times]
    out = []
    for image in images:
        if not isinstance(image, np.ndarray) or image.shape[:2] != CHECK_SIZE[::-1]:
            raise StageFileError(f"the stage rendered {type(image).__name__}, not a {CHECK_SIZE} image")
        out.append(to_uint8(image))
    return out


def render_file(file: Path, ex: Exercise) -> list[np.ndarray]:
    """Render the learner's file. A scene step's shader changes the process's shader folder: call this in a
    process of its own (sandbox.py does)."""
    if ex.shader:
        return render_shader(file, ex)
    return render_class(stage_class(load_module(file), ex), ex)


def render_shader(file: Path, ex: Exercise) -> list[np.ndarray]:
    """The step's scene drawn with the learner's shader in place of the path's own (a copy of the path's shader
    folder with the one file replaced, named by the path's override variable) at the scene references' size."""
    from wgpurender.exercises.source import shader_folder

    with tempfile.TemporaryDirectory(prefix="wgpurender-shaders-") as name:
        folder = Path(name)
        shutil.copytree(shader_folder(ex.path), folder, dirs_exist_ok=True)
        shutil.copyfile(file, folder / ex.shader)
        return [to_uint8(_render_scene(ex, folder))]


def _render_scene(ex: Exercise, folder: Path) -> np.ndarray:
    """The learner's scene, drawn as the references were made: the scene's own anisotropy (REFERENCE_ANISOTROPY,
    core/plan/anisotropy.py)."""
    from wgpurender.core.files.assets import scene_dir
    from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY

    scene = scene_dir() / f"{ex.scene}.toml"
    if ex.path == "wgpu":
        from wgpurender.wgpu_path.device.shaders import SHADER_DIR_ENV
        from wgpurender.wgpu_path.scene import render_scene_file

        os.environ[SHADER_DIR_ENV] = str(folder)
        return render_scene_file(scene, size=SCENE_CHECK_SIZE, frames=1, anisotropy=REFERENCE_ANISOTROPY).pixels
    from wgpurender.raw_path.device.shaders import GLSL_DIR_ENV
    from wgpurender.raw_path.scene import render_scene_reference

    os.environ[GLSL_DIR_ENV] = str(folder)
    return render_scene_reference(scene, size=SCENE_CHECK_SIZE, anisotropy=REFERENCE_ANISOTROPY)


def render_source(source: str, ex: Exercise) -> list[np.ndarray]:
    """Render stage source text (the solution or a mistake variant: our own code) in this process."""
    with tempfile.TemporaryDirectory(prefix="wgpurender-exercise-") as folder:
        file = Path(folder) / f"stage_{hashlib.sha1(source.encode()).hexdigest()[:12]}.py"
        file.write_text(source, encoding="utf-8")
        try:
            return render_file(file, ex)
        except StageFileError as err:  # our own variant is broken: a bug, not a verdict
            raise UserError(f"step {ex.step} ({ex.path}): a catalogue variant does not load: {err}") from None
