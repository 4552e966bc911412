"""Reading a scene file: TOML text parsed, then validated part by part into a :class:`Scene`."""

from __future__ import annotations

import dataclasses
import tomllib
from pathlib import Path

from wgpurender.core.errors import UserError
from wgpurender.core.files.assets import resolve_scene
from wgpurender.core.files.input_files import MAX_NESTING, input_file, nesting_depth
from wgpurender.core.scene import toml_cache
from wgpurender.core.scene.checker import Checker
from wgpurender.core.scene.environment_block import parse_environment
from wgpurender.core.scene.file_materials import read_file_materials
from wgpurender.core.scene.model import Scene
from wgpurender.core.scene.model_motion import read_motion
from wgpurender.core.scene.validate import (
    TOP_KEYS,
    _camera,
    _lights,
    _material,
    _models,
    _post,
    _render,
    file_camera_choice,
    resolve_file_camera,
)
from wgpurender.core.view import garbage


def parse_scene(text: str, path: str | Path = "<scene>") -> Scene:
    """Validate TOML text as a scene whose file is ``path`` (relative paths resolve from its folder)."""
    path = Path(path).absolute()
    try:
        data = toml_cache.loads(text)  # a large scene's values parsed once (a verified cache)
    except tomllib.TOMLDecodeError as err:
        raise UserError(f"{path}: invalid TOML: {err}") from None
    except RecursionError:  # tomllib recurses once per nested array or inline table
        data = None
    if data is None or nesting_depth(data) > MAX_NESTING:
        raise UserError(f"{path}: tables and arrays are nested more than {MAX_NESTING} deep; a scene needs 3 "
                        "(e.g. [[models]] with a position array)")
    c = Checker(path, text)
    c.table(data, (), TOP_KEYS, required=("camera",))
    materials = {}
    mats = data.get("materials", {})
    c.table(mats, ("materials",), tuple(mats) if isinstance(mats, dict) else ())
    for name, body in mats.items():
        materials[name] = _material(c, body, ("materials", name), name, f"[materials.{name}]")
    description = data.get("description", "")
    choice = file_camera_choice(c, data["camera"])
    camera = _camera(c, data["camera"]) if choice is None else None
    models = tuple(_with_file_data(m) for m in _models(c, data.get("models", []), materials))
    scene = Scene(
        path=path,
        camera=camera if choice is None else resolve_file_camera(c, choice, models),
        models=models,
        materials=materials,
        lights=_lights(c, data.get("lights", [])),
        render=_render(c, data.get("render", {})),
        post=_post(c, data.get("post", [])),
        description=c.string(description, ("description",)),
        environment=parse_environment(c, data.get("environment")),
    )
    if not any(m.suffix in (".gltf", ".glb") for m in scene.models):
        return scene
    from wgpurender.core.scene.gltf_lights import scene_lights  # imported only for glTF models

    return dataclasses.replace(scene, lights=scene_lights(scene.lights, scene.models, path))  # + KHR lights


def _with_file_data(model):
    """The model with the materials and motion its file gives (read once, here), or itself when its file gives
    neither (most models of a large scene: not copied)."""
    found, motion = read_file_materials(model), read_motion(model)
    if found is None and not motion:
        return model
    return dataclasses.replace(model, file_materials=found, motion=motion)


@garbage.paused()  # ~10^5 long-lived objects for 10k models: no collection walks them on the way
def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file (or the bundled scene ``path`` names: :mod:`wgpurender.core.files.assets`)."""
    path = input_file(resolve_scene(path), "scene file")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        raise UserError(f"cannot read scene file {path}: {err}") from None
    return parse_scene(text, path)
