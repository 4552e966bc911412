"""What the demo window shows: a stage or a scene file, rebuilt from its files on demand, with an orbit camera.

A :class:`DemoView` builds the drawable (a :class:`~wgpurender.wgpu_path.stages.base.Stage` or a
:class:`~wgpurender.wgpu_path.scene.SceneRenderer`) for the surface's format, records which
WGSL files that took (plus the scene file itself) for live reload, and moves the drawable's
camera to the orbit's pose. Scenes and the 3d stage have a camera; the other stages are
flat and ignore camera input.

The start pose comes from where the headless renderer gets it: the scene file's
``[camera]``, or the 3d stage's own camera constants (whatever the stage is built with).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.core.view.orbit import Orbit, follow, moved_camera
from wgpurender.wgpu_path.device.context import GPUContext


class DemoView:
    """``build(fmt)`` makes a fresh drawable from the files as they are now; ``watched`` lists those files."""

    def __init__(self, ctx: GPUContext, target: str, msaa: int | None = None,
                 anisotropy: str = DEFAULT_ANISOTROPY) -> None:
        self.ctx, self.target, self.msaa, self.anisotropy = ctx, target, msaa, anisotropy
        from wgpurender.core.course.formats import is_scene_file

        self.is_scene = is_scene_file(target)
        self.watched: set[Path] = set()
        self.orbit: Orbit | None = None
        self._start_pose: tuple | None = None
        self.live = None  # core.plan.live.LiveKnobs while the overlay turns the knobs (start_live)

    def start_live(self):
        """Let the overlay turn the knobs from now on: their values start at this view's options."""
        from wgpurender.core.plan.live import LiveKnobs

        if self.is_scene:
            from wgpurender.core.scene import load_scene

            self.live = LiveKnobs.for_scene(load_scene(self.target), self.msaa, self.anisotropy)
        else:
            self.live = LiveKnobs(msaa=self.msaa)
        return self.live

    def effect_names(self) -> list[str]:
        if not self.is_scene:
            return []
        from wgpurender.core.scene import load_scene

        return [step.effect for step in load_scene(self.target).post]

    def check(self) -> None:
        """Fail on a bad stage name, scene file or option before a window opens, as cheaply as possible.

        A scene is loaded and planned (no GPU work: building its renderer twice cost a second of start-up on
        lavapipe); a stage is built, which is cheap and runs the stage's own option checks.
        """
        if self.is_scene:
            self.plan("rgba8unorm-srgb")
        else:
            self._make("rgba8unorm-srgb")

    def build(self, fmt: str, keep_caches: bool = False):
        """A new drawable, its first frame's shaders included (pipelines made lazily are made in ``warm``).
        ``keep_caches``: a knob changed, not a file: the device's cached pipelines and samplers are reused."""
        from wgpurender.wgpu_path.device.shaders import recording_loads
        from wgpurender.wgpu_path.window.live_reload import drop_shader_caches

        if not keep_caches:
            drop_shader_caches(self.ctx.device)
        with recording_loads() as loaded:
            drawable = self._make(fmt)
        self.watched = set(loaded) | ({Path(self.target).resolve()} if self.is_scene else set())
        self._adopt_camera(drawable)
        return drawable

    def record_lazy_loads(self):
        """A context manager for the first draw of a new drawable: shaders it loads join ``watched``."""
        from contextlib import contextmanager

        from wgpurender.wgpu_path.device.shaders import recording_loads

        @contextmanager
        def block():
            with recording_loads() as loaded:
                yield
            self.watched |= loaded

        return block()

    def plan(self, fmt: str):
        """The scene's plan for this adapter and a swapchain of ``fmt`` (:func:`wgpurender.core.plan.resolve_plan`),
        from the file as it is now; a swapchain image is not a storage texture, so a compute post path writes
        it through a scratch copy (``output_storage=False``)."""
        from wgpurender.core.plan import resolve_plan

        if self.live is not None:  # the overlay's knobs, through the same resolution function
            from wgpurender.core.scene import load_scene

            return self.live.resolve(load_scene(self.target), self.ctx.adapter_facts(), fmt)
        return resolve_plan(self.target, self.ctx.adapter_facts(), output_format=fmt, msaa=self.msaa,
                            anisotropy=self.anisotropy, output_storage=False)

    def _make(self, fmt: str):
        if self.is_scene:
            from wgpurender.wgpu_path.scene import SceneRenderer

            plan = self.plan(fmt)
            return SceneRenderer(self.ctx, plan.scene, plan)
        from wgpurender.wgpu_path.stages import get_stage

        return get_stage(self.target)(self.ctx, fmt, self.msaa if self.live is None else self.live.msaa)

    # -- the camera ------------------------------------------------------------------
    @staticmethod
    def _camera_of(drawable):
        """(eye, target, up) of the drawable's camera, or None for a flat stage."""
        if hasattr(drawable, "scene_pass"):
            cam = drawable.scene_pass.scene.camera
        else:
            cam = getattr(drawable, "camera", None)
        if cam is None:
            return None
        return tuple(cam.eye), tuple(cam.target), tuple(cam.up)

    def _adopt_camera(self, drawable) -> None:
        """Start the orbit at the drawable's camera; keep the user's orbit when a rebuild left that camera alone."""
        pose = self._camera_of(drawable)
        if pose is None:
            self.orbit = self._start_pose = None
            return
        if pose != self._start_pose or self.orbit is None:
            self.orbit = Orbit.from_look_at(*pose)
            self._start_pose = pose

    def follow(self, drawable) -> None:
        """After ``play(t)``: an animated file camera moves the orbit with it (core/view/orbit.follow)."""
        if hasattr(drawable, "scene_pass"):
            self.orbit, self._start_pose = follow(self.orbit, self._start_pose, drawable.scene_pass.scene.camera)

    def apply_camera(self, drawable) -> None:
        """Move the drawable's camera to the orbit's eye and target (a no-op for flat stages)."""
        if self.orbit is None:
            return
        if hasattr(drawable, "scene_pass"):
            scene = drawable.scene_pass.scene
            camera = moved_camera(scene.camera, self.orbit)
            if camera is not scene.camera:
                drawable.scene_pass.scene = dataclasses.replace(scene, camera=camera)
        elif getattr(drawable, "camera", None) is not None:
            drawable.camera = moved_camera(drawable.camera, self.orbit)
