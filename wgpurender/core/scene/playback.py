"""Playing a scene's glTF animations in the window: which models animate, and the scene and vertices at a time.

The windows draw one time per frame from their clock (core/view/controls.PausableClock: P pauses it). For each
glTF model whose file has an animation (the one its [[models]] block names, or the first), that time loops at the
clip's end (its channels' largest key time): the model is posed at ``t mod end``. A still scene has no tracks
(:func:`tracks` is empty) and pays nothing per frame: the paths make no :class:`Playback` for it.

What moves per frame, made here once for both paths (so both draw the same frame for the same time):

- the vertices of each animated model's meshes, re-posed on the CPU (nodes and skins, as core/models/mesh.load_mesh
  poses them, from the document parsed at load), of which each path writes the rows from the first to the last
  vertex that moved over that mesh's own range of its shared vertex buffer (core/plan/meshes.changed_rows);
- the view when it is a file camera on an animated node, and the file's KHR lights (model_motion.placed_again).

The offscreen render at ``--time t`` (model_motion.at_time) poses the same models at the same ``t``, so frame k
of the window at time t equals it while ``t`` is within the clip (past the end, the window loops where
``--time`` clamps, as glTF's own sampling does).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from wgpurender.core.models import gltf_animation
from wgpurender.core.scene.model import Scene
from wgpurender.core.scene.model_motion import GLTF_SUFFIXES, placed_again


@dataclass(frozen=True)
class Track:
    """Model ``model`` (its index in the scene) plays ``animation`` (as its block names it), looping at ``end`` s."""

    model: int
    animation: int | str | None
    end: float

    def local_time(self, t: float) -> float:
        """The clip time at clock time ``t``: ``t`` looped at the clip's end (a clip of one key: always 0)."""
        if self.end <= 0.0 or not math.isfinite(t):
            return 0.0
        return t % self.end


def tracks(scene: Scene) -> tuple[Track, ...]:
    """One track per glTF model whose file has an animation with keys on a node (none: a still scene)."""
    from wgpurender.core.scene.gltf_materials import document  # the parsed file, read once while unchanged

    found = []
    for i, model in enumerate(scene.models):
        if model.suffix not in GLTF_SUFFIXES or not model.motion:
            continue  # motion: the load's lines, one at least for a file with animations (model_motion)
        doc = document(str(model.path))
        if not doc.json.get("animations"):
            continue
        animation = model.pose.animation if model.pose is not None else None
        clip = gltf_animation.choose(doc, animation)
        ends = [times[-1] for _, _, times, _, _ in gltf_animation.read_channels(doc, clip)]
        if ends:
            found.append(Track(i, animation, float(max(ends))))
    return tuple(found)


def scene_at(scene: Scene, playing: tuple[Track, ...], t: float) -> Scene:
    """``scene`` with each track's model posed at its clip time for clock time ``t``, and the file camera and
    KHR lights its nodes carry placed again."""
    models = list(scene.models)
    for track in playing:
        pose = gltf_animation.Pose(track.animation, track.local_time(t))
        models[track.model] = dataclasses.replace(models[track.model], pose=pose)
    return placed_again(scene, tuple(models))


def describe(playing: tuple[Track, ...], scene: Scene) -> list[str]:
    """``--explain``'s lines: what the window plays (nothing for a still scene)."""
    return [f"window plays {scene.models[k.model].path.name} (model {k.model}), animation "
            f"{0 if k.animation is None else k.animation!r}, looping every {k.end:g} s: its vertices re-posed on the "
            "CPU and rewritten in place each frame (offscreen: --time T)" for k in playing]


class Playback:
    """The per-frame work of one scene's tracks: :meth:`frame` gives the scene and the re-posed meshes at ``t``.

    ``load(key, pose)`` loads a mesh as the path's plan meshes do (``PlanMeshes.posed`` in core/plan/meshes.py),
    so a re-posed mesh has the attributes the buffers hold. Nothing is re-posed when a model's clip time is the one
    drawn last (a paused clock writes nothing)."""

    def __init__(self, scene: Scene, playing: tuple[Track, ...], load) -> None:
        self.scene, self.playing, self.load = scene, playing, load
        self._drawn: dict[int, float] = {}

    @classmethod
    def of(cls, scene: Scene, playing: tuple[Track, ...], load) -> Playback | None:
        """A playback of the plan's tracks (``RenderPlan.playing``), or None when there are none (a still scene
        pays nothing)."""
        return cls(scene, playing, load) if playing else None

    def frame(self, t: float):
        """(the scene at ``t``, {(path, pose drawn at load): re-posed Mesh} of the models whose pose changed)."""
        scene = scene_at(self.scene, self.playing, t)
        moved = {}
        for track in self.playing:
            local = track.local_time(t)
            if self._drawn.get(track.model) == local:
                continue
            self._drawn[track.model] = local
            model = self.scene.models[track.model]
            key = (model.path, model.pose)
            moved[key] = self.load(key, scene.models[track.model].pose)
        return scene, moved
