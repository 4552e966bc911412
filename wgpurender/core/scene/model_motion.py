"""What moves a glTF model's vertices, read once when the scene loads: the animation its [[models]] block poses
(``time``, ``animation``) and the skins its nodes carry, as ``--explain`` lines (``Model.motion``).

Reading it here also checks the pose against the file before anything is drawn: an animation the file does not
have, or a time given for a file without animations, is one line at load (core/models/gltf_animation.choose).
The posed vertices themselves are made when the mesh loads (core/models/mesh.load_mesh with the model's pose).
"""

from __future__ import annotations

import dataclasses

from wgpurender.core.errors import UserError
from wgpurender.core.models import gltf_animation
from wgpurender.core.scene.model import Model, Scene

GLTF_SUFFIXES = (".gltf", ".glb")


def read_motion(model: Model) -> tuple[str, ...]:
    """``--explain``'s lines for the model's animation and skins (none for other formats or a still file)."""
    if model.suffix not in GLTF_SUFFIXES:
        return ()
    from wgpurender.core.scene.gltf_materials import document  # the parsed file, shared with its materials

    return tuple(gltf_animation.pose_notes(document(str(model.path)), model.pose))


def at_time(scene: Scene, t: float) -> Scene:
    """The scene with every glTF model that has animations posed at ``t`` seconds (``--time``: it overrides a
    model block's ``time``, keeping its ``animation``); one line when no model has an animation (the flag would
    change nothing)."""
    from wgpurender.core.scene.gltf_materials import document

    models, posed = [], 0
    for model in scene.models:
        if model.suffix in GLTF_SUFFIXES and document(str(model.path)).json.get("animations"):
            model = dataclasses.replace(model, pose=gltf_animation.Pose(model.pose.animation if model.pose else None,
                                                                       t))
            model = dataclasses.replace(model, motion=read_motion(model))
            posed += 1
        models.append(model)
    if not posed:
        raise UserError(f"scene {str(scene.path)!r} is static: none of its models is a glTF file with an animation, so "
                        f"a time ({t:g} s) would change nothing (leave --time out; it animates stages and glTF "
                        "animations)")
    return placed_again(scene, tuple(models))


def placed_again(scene: Scene, models: tuple[Model, ...]) -> Scene:
    """``scene`` with ``models`` (newly posed) and what their nodes place placed again at the new pose: the view
    when it is a file camera, and the models' KHR_lights_punctual lights (the scene's own lights stay)."""
    from wgpurender.core.scene.gltf_cameras import file_camera
    from wgpurender.core.scene.gltf_lights import scene_lights

    camera = scene.camera
    if camera.file_camera is not None:
        model, index = camera.file_camera
        camera = file_camera(models[model], index)
    own = tuple(light for light in scene.lights if not light.origin)  # a model's lights carry their origin
    return dataclasses.replace(scene, models=models, camera=camera, lights=scene_lights(own, models, scene.path))
