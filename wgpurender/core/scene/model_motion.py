"""What moves a glTF model's vertices, read once when the scene loads: the animation its [[models]] block poses
(``time``, ``animation``) and the skins its nodes carry, as ``--explain`` lines (``Model.motion``).

Reading it here also checks the pose against the file before anything is drawn: an animation the file does not
have, or a time given for a file without animations, is one line at load (core/models/gltf_animation.choose).
The posed vertices themselves are made when the mesh loads (core/models/mesh.load_mesh with the model's pose).
"""

from __future__ import annotations

from wgpurender.core.models import gltf_animation
from wgpurender.core.scene.model import Model

GLTF_SUFFIXES = (".gltf", ".glb")


def read_motion(model: Model) -> tuple[str, ...]:
    """``--explain``'s lines for the model's animation and skins (none for other formats or a still file)."""
    if model.path.suffix.lower() not in GLTF_SUFFIXES:
        return ()
    from wgpurender.core.scene.gltf_materials import document  # the parsed file, shared with its materials

    return tuple(gltf_animation.pose_notes(document(str(model.path)), model.pose))
