"""One resolved plan for every entry point: the knobs decided once, per adapter, by :func:`resolve_plan`.

``wgpurender render``, ``reference``, ``demo`` (both windows), the Python API (``render``, ``reference``,
``explain``), ``report``, ``verify`` and ``bench`` all draw the plan this function returns, each for the
adapter it draws on (the wgpu path: :meth:`wgpurender.wgpu_path.device.context.GPUContext.adapter_facts`; the raw
path: :meth:`wgpurender.raw_path.device.context.VulkanContext.adapter_facts`; both made by
:meth:`~wgpurender.core.plan.model.AdapterFacts.of`). No other function builds a plan: ``build_plan`` is called
here only, and :meth:`RenderPlan.with_knobs` resolves again through :func:`resolve_knobs`. So the same scene and
flags on the same device give the same plan whichever way it is asked for, and ``--explain`` prints the plan that
was drawn.

The flags: ``size``, ``output_format``, ``msaa`` (the scene's [render] overridden, as the CLI's --size,
--format, --msaa), ``anisotropy`` (:data:`DEFAULT_ANISOTROPY`, the per-adapter rule of
wgpurender/core/plan/anisotropy.py, or "scene") and any other :class:`~wgpurender.core.plan.model.Knobs` field
(post_path, post_fuse, immediates, depth_format, reverse_z, scene_format, output_storage).
"""

from __future__ import annotations

import dataclasses
import os
import sys

from wgpurender.core.errors import UserError
from wgpurender.core.plan.anisotropy import ANISOTROPY_RULES, DEFAULT_ANISOTROPY
from wgpurender.core.plan.build import build_plan
from wgpurender.core.plan.model import AdapterFacts, Knobs, RenderPlan
from wgpurender.core.scene import Scene, load_scene
from wgpurender.core.scene.model_motion import at_time
from wgpurender.core.view import garbage

_NOT_FLAGS = ("adapter", "anisotropy")  # set from the arguments, never passed as a knob
KNOB_FLAGS = tuple(k for k in Knobs.__dataclass_fields__ if k not in _NOT_FLAGS)


@garbage.paused()  # a plan of 10k draws: no collection walks them on the way (core/view/garbage.py)
def resolve_plan(target: Scene | str | os.PathLike, adapter: AdapterFacts | None, *,
                 size: tuple[int, int] | None = None, output_format: str | None = None, msaa: int | None = None,
                 anisotropy: str = DEFAULT_ANISOTROPY, camera: int | None = None, time: float | None = None,
                 **knobs) -> RenderPlan:
    """The plan of a scene (or scene file) for ``adapter``, every "auto" knob decided for it.

    ``adapter`` None: not known (no GPU, or a plan printed before one is chosen); the "auto" knobs then
    keep the scene's values and say so. Unknown knob names raise UserError. ``camera`` (``--camera K``): the
    view is camera K of the scene's glTF model instead of its ``[camera]`` (core/scene/gltf_cameras.py).
    ``time`` (``--time``; None or 0: the scene's own): every glTF model with an animation posed at that time
    (core/scene/model_motion.at_time), once, here; a scene without one refuses it.
    """
    unknown = sorted(set(knobs) - set(KNOB_FLAGS))
    if unknown:
        raise UserError(f"unknown plan knob {unknown[0]!r}: choose from {', '.join(KNOB_FLAGS)}")
    if anisotropy not in ANISOTROPY_RULES:
        raise UserError(f"anisotropy {anisotropy!r}: choose one of {', '.join(ANISOTROPY_RULES)}")
    scene = target if isinstance(target, Scene) else load_scene(target)
    if time:
        scene = at_time(scene, time)
    if camera is not None:
        from wgpurender.core.scene.gltf_cameras import with_file_camera

        scene = with_file_camera(scene, camera)
    plan = build_plan(scene, size=size, output_format=output_format, msaa=msaa,
                      knobs=Knobs(adapter=adapter, anisotropy=anisotropy, **knobs))
    return dataclasses.replace(plan, rebuild=resolve_knobs)


def resolve_knobs(scene: Scene, knobs: Knobs, **overrides) -> RenderPlan:
    """:func:`resolve_plan` with the knobs as one :class:`Knobs` (what :meth:`RenderPlan.with_knobs` calls)."""
    flags = {k: getattr(knobs, k) for k in KNOB_FLAGS}
    return resolve_plan(scene, knobs.adapter, anisotropy=knobs.anisotropy, **flags, **overrides)


def explain_scene(path: str | os.PathLike, adapter: AdapterFacts | None = None, **flags) -> str:
    """The resolved plan of a scene file as text: what ``render SCENE.toml --explain`` prints for ``adapter``."""
    return resolve_plan(path, adapter, **flags).explain()


def main(argv: list[str] | None = None) -> int:
    """``python -m wgpurender.core.plan SCENE.toml``: print the plan (no adapter: the "auto" knobs left open);
    UserError -> one line, exit 2."""
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1 or args[0] in ("-h", "--help"):
        print("usage: python -m wgpurender.core.plan SCENE.toml", file=sys.stderr)
        return 2
    try:
        sys.stdout.write(explain_scene(args[0]))
    except UserError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    return 0
