"""A frame of a scene: the scene pass into the plan's attachments, then the post chain into the output.

The plan (wgpurender/core/plan/) decides everything; this module only builds what it lists:

- ``msaa_color`` (4 samples) only at msaa 4, resolved at the end of the scene pass into
  ``scene_color`` (with a post chain) or straight into the output (without one);
- ``depth`` (depth32float, as many samples as the colour) only when there are models;
- ``scene_color`` (rgba16float when HDR) only when a post chain reads it;
- the post passes' intermediates, FXAA's mask and the compute path's scratch, as the plan lists them;
- the post passes themselves from the plan (:class:`wgpurender.wgpu_path.post.PostRunner`), never from the scene.

A plan built without an adapter (``--explain`` with no GPU, a test) is re-planned here for this
device (``ctx.adapter_facts()``), so its "auto" knobs (post path, immediates) are decided, and the
renderer builds exactly what ``renderer.plan.explain()`` says. Why the post chain is passes, not
subpasses, and what fusing them changes: wgpurender/wgpu_path/post/chain.py.
"""

from __future__ import annotations

import dataclasses
import functools
from pathlib import Path

import wgpu

from wgpurender.core.errors import UserError
from wgpurender.core.plan import RenderPlan, gpu_memory, resolve_plan
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.core.scene import Scene, load_scene
from wgpurender.core.scene.playback import Playback
from wgpurender.core.view import garbage
from wgpurender.wgpu_path.device.context import GPUContext, get_context
from wgpurender.wgpu_path.device.frame_loop import RenderResult, run_frame, run_frames
from wgpurender.wgpu_path.device.gpu_cache import GpuCache
from wgpurender.wgpu_path.device.targets import TARGET_USAGE, create_target
from wgpurender.wgpu_path.post import PostRunner, attachment_usage, output_usage
from wgpurender.wgpu_path.scene.resources import SceneResources
from wgpurender.wgpu_path.scene.scene_pass import ScenePassRenderer

ATTACHMENT_USAGE = {
    "msaa-color": wgpu.TextureUsage.RENDER_ATTACHMENT,
    "depth": wgpu.TextureUsage.RENDER_ATTACHMENT,
    # COPY_SRC: so the pre-post image can be read back (tests, debugging); it costs nothing per frame.
    "scene-color": wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_SRC,
}


def plan_for_device(ctx: GPUContext, plan: RenderPlan) -> RenderPlan:
    """The plan with its adapter known (unchanged when it already was, or when it was not built from a scene)."""
    if plan.knobs.adapter is not None or plan.scene is None:
        return plan
    return plan.with_knobs(adapter=ctx.adapter_facts())


class SceneRenderer:
    """Draws one scene by its plan into any texture of the plan's output format (offscreen or swapchain).

    ``resize(size)`` makes the size-dependent attachments; ``record(encoder, target, t)`` records a frame.
    ``t`` does not change the image; the window calls ``play(t)`` first, which poses glTF animations at ``t``.
    """

    @garbage.paused()  # 10k meshes, buffers and draws: no collection walks them on the way (core/view/garbage.py)
    def __init__(self, ctx: GPUContext, scene: Scene, plan: RenderPlan) -> None:
        plan = plan_for_device(ctx, plan)
        self.ctx, self.scene, self.plan = ctx, scene, plan
        self._check_limits()
        self.resources = SceneResources(ctx, plan)
        self.scene_pass = ScenePassRenderer(ctx, scene, plan, self.resources, plan.immediates)
        self.chain = PostRunner(ctx, plan.post_passes)
        self.target_usage = output_usage(plan.post_passes)  # what the output texture needs beyond TARGET_USAGE
        self.size: tuple[int, int] | None = None
        self.attachments: dict[str, wgpu.GPUTexture] = {}
        self._scene_pass = plan.scene_pass
        self._views: dict[str, tuple[wgpu.GPUTexture, wgpu.GPUTextureView]] = {}  # name -> (texture, its view)
        # target texture -> its bound untimed frame (_bind); a swapchain's new texture each frame cannot grow it
        self._frames: GpuCache = GpuCache("scene-frames", 4)
        self._target_format = plan.target_format  # a property of the plan: read once, checked every new target
        self._bound = None  # finish(target) -> frame: the frame bound to this size's attachments (_bind_size)
        self.playback = Playback.of(scene, plan.playing, self.resources.meshes.posed)  # None: a still scene

    def play(self, t: float) -> int:
        """Pose the scene's animated glTF models at clock time ``t`` (the window's, once per frame; looped at each
        clip's end: core/scene/playback.py): their vertices rewritten in place, the file camera and KHR lights
        placed again. The number of buffer writes (0 for a still scene or an unchanged pose)."""
        if self.playback is None:
            return 0
        scene, moved = self.playback.frame(t)
        self.scene = self.scene_pass.scene = dataclasses.replace(self.scene, models=scene.models, lights=scene.lights,
                                                                 camera=scene.camera)
        return sum(self.resources.rewrite(key, mesh) for key, mesh in moved.items())

    def move_camera(self, camera) -> None:
        """Use ``camera`` from the next frame on (the pass uploads it when it changed): slow-motion measurements."""
        self.scene = dataclasses.replace(self.scene, camera=camera)
        self.scene_pass.scene = self.scene

    def create_output(self, label: str = "scene-output") -> wgpu.GPUTexture:
        """An offscreen output texture for this plan: its size, format and every usage the plan's passes need.

        On the compute post path a pass may write the output directly (STORAGE_BINDING), so a texture made
        by hand with the plain target usage fails there; headless callers take their target from here.
        """
        return create_target(self.ctx, self.plan.size, self.plan.target_format, usage=TARGET_USAGE | self.target_usage,
                             label=label)

    def _format_mismatch(self, got: str) -> str:
        plan = self.plan
        if plan.target_format != plan.output_format:
            return (f"the scene was planned for {plan.output_format} output, written by a compute pass into its "
                    f"storage twin {plan.target_format}, but the target is {got}: make the target with "
                    "renderer.create_output(), or plan with output_storage=False to write an existing texture")
        return (f"the scene was planned for {plan.output_format} output, but the target is {got}: build the plan "
                f"with output_format={got!r}")

    def _check_limits(self) -> None:
        max_dim = self.ctx.limit("max-texture-dimension-2d")
        w, h = self.plan.size
        if max(w, h) > max_dim:
            raise UserError(f"render size {w}x{h} is larger than this GPU's max-texture-dimension-2d ({max_dim}): "
                            "choose a smaller [render] size or --size")
        gpu_memory.check_memory(gpu_memory.plan_textures(self.plan), self.ctx.adapter.info["adapter_type"],
                                f"{self.plan.scene_path.name} at {w}x{h}, msaa {self.plan.msaa}")

    def resize(self, size: tuple[int, int]) -> None:
        """(Re)create the plan's attachments other than the output at ``size``."""
        size = (int(size[0]), int(size[1]))
        if size == self.size:
            return
        self.size = size
        self.attachments = {}
        self._frames.clear()  # bound frames name the old attachments
        self._bound = None
        for a in self.plan.attachments:
            usage = ATTACHMENT_USAGE.get(a.role, 0) | attachment_usage(a, self.plan.post_passes)
            if a.role != "output" and usage:
                self.attachments[a.name] = self.ctx.device.create_texture(
                    label=a.name, size=(size[0], size[1], 1), format=a.format, sample_count=a.sample_count,
                    usage=usage)

    def _texture(self, name: str, target: wgpu.GPUTexture) -> wgpu.GPUTexture:
        return target if name == "output" else self.attachments[name]

    def _view(self, name: str, target: wgpu.GPUTexture) -> wgpu.GPUTextureView:
        """A view of an attachment or the output, made once per texture object (resize makes new ones)."""
        texture = self._texture(name, target)
        cached = self._views.get(name)
        if cached is None or cached[0] is not texture:
            cached = self._views[name] = (texture, texture.create_view())
        return cached[1]

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0, timer=None) -> None:
        """Record the frame into ``encoder``; ``timer``: an optional timing.PassTimer (one entry per pass).

        Untimed (as a window draws), the frame is bound once per size (:meth:`_bind_size`): its checks, views,
        attachment dicts and post steps are made then, and each frame makes only the wgpu calls. A new target
        texture of that size (a swapchain's image each frame) finishes only what names it (:meth:`_bind`).
        """
        if timer is None:
            self._frames.get(target, lambda: self._bind(target))(encoder)
            return
        self._check_target(target)
        scene_pass = self._scene_bound(target)
        scene_pass(encoder, timer.writes("scene"))
        if self.chain:
            self.chain.run(encoder, {**self.attachments, "output": target}, timer=timer)

    def _check_target(self, target: wgpu.GPUTexture) -> None:
        """Refuse a target of another format; (re)make the attachments at its size."""
        if target.format != self._target_format:
            raise UserError(self._format_mismatch(target.format))
        size = target.size
        self.resize((size[0], size[1]))

    def _scene_bound(self, target: wgpu.GPUTexture | None):
        """The scene pass bound to this size's attachments (and ``target`` where the pass writes the output)."""
        sp = self._scene_pass
        color = {"view": self._view(sp.color, target), "clear_value": sp.clear_color,
                 "load_op": "clear", "store_op": "store"}
        if sp.resolve_target is not None:
            # The multisampled image is scratch: resolved at the end of the pass, its samples discarded.
            color.update(resolve_target=self._view(sp.resolve_target, target), store_op="discard")
        depth = self._view(sp.depth, target) if sp.depth else None
        return self.scene_pass.bound([color], depth, self.size[0] / self.size[1])

    def _bind(self, target: wgpu.GPUTexture):
        """The untimed frame into ``target``: ``_bind(target)(encoder)`` records it (kept in ``_frames``). What
        does not name the target is bound once per size; a new target of that size costs only what names it."""
        self._check_target(target)
        if self._bound is None:
            self._bound = self._bind_size()
        return self._bound(target)

    def _bind_size(self):
        """``finish(target) -> frame``: the frame bound to this size's attachments (issue 31.4, the window's
        swapchain image is a new texture object each frame). Only the scene pass when it writes the output (no
        post chain) and the post steps that name the output (its last pass's view, or its copy) wait for it."""
        sp = self._scene_pass
        scene_pass = None if "output" in (sp.color, sp.resolve_target) else self._scene_bound(None)
        chain = self.chain.bind(self.attachments) if self.chain else None

        def finish(target: wgpu.GPUTexture):
            return functools.partial(_record_frame, scene_pass or self._scene_bound(target),
                                     chain(target) if chain is not None else None)

        return finish


def _record_frame(scene_pass, chain, encoder: wgpu.GPUCommandEncoder) -> None:
    scene_pass(encoder)
    if chain is not None:
        chain(encoder)


def load_renderer(path: str | Path, ctx: GPUContext, *, size: tuple[int, int] | None = None, fmt: str | None = None,
                  msaa: int | None = None, use_immediates: bool | None = None,
                  knobs: dict | None = None, anisotropy: str = DEFAULT_ANISOTROPY) -> SceneRenderer:
    """A renderer for a scene file, planned by :func:`wgpurender.core.plan.resolve_plan` for this context's
    adapter; ``size``, ``fmt`` and ``msaa`` override the scene's; ``knobs``: plan knobs (e.g.
    ``{"post_fuse": False}``); ``anisotropy``: the rule of wgpurender/core/plan/anisotropy.py.
    """
    knobs = dict(knobs or {})
    if use_immediates is not None:
        knobs["immediates"] = "on" if use_immediates else "off"
    scene = load_scene(path)
    plan = resolve_plan(scene, ctx.adapter_facts(), size=size, output_format=fmt, msaa=msaa, anisotropy=anisotropy,
                        **knobs)
    return SceneRenderer(ctx, scene, plan)


def render_frame(ctx: GPUContext, renderer: SceneRenderer, target: wgpu.GPUTexture, t: float = 0.0):
    """Record, submit and read back one frame: (pixels, wall milliseconds including the readback)."""
    frame = run_frame(ctx, renderer.record, target, t, label="scene-frame")
    return frame.pixels, frame.frame_ms


def render_plan(ctx: GPUContext, plan: RenderPlan, t: float = 0.0, *, frames: int = 3) -> RenderResult:
    """Render a resolved plan headless: a :class:`wgpu_path.render.RenderResult` of the last of ``frames``
    frames, whose ``plan`` is the plan drawn (``plan`` itself when it was resolved for this context's adapter).

    The first frame pays for texture uploads, mip generation and shader compilation, so
    ``frame_ms`` is the last (steady-state) frame: record, submit, GPU work and readback.
    """
    if plan.scene is None:
        raise UserError("this plan was not built from a scene: resolve it with resolve_plan(scene, adapter)")
    renderer = SceneRenderer(ctx, plan.scene, plan)
    target = renderer.create_output()
    frame = run_frames(ctx, renderer.record, target, frames, t, label="scene-frame")
    return RenderResult(pixels=frame.pixels, frame_ms=frame.frame_ms, adapter=ctx.describe(), plan=renderer.plan)


def render_scene_file(path: str | Path, size: tuple[int, int] | None = None, fmt: str | None = None,
                      msaa: int | None = None, t: float = 0.0, ctx: GPUContext | None = None, *,
                      frames: int = 3, use_immediates: bool | None = None, knobs: dict | None = None,
                      anisotropy: str = DEFAULT_ANISOTROPY) -> RenderResult:
    """Render a scene file headless (:func:`render_plan` of its plan for this context's adapter)."""
    ctx = ctx or get_context()
    renderer = load_renderer(path, ctx, size=size, fmt=fmt, msaa=msaa, use_immediates=use_immediates, knobs=knobs,
                             anisotropy=anisotropy)
    return render_plan(ctx, renderer.plan, t, frames=frames)


def scene_drawable_factory(path: str | Path, ctx: GPUContext, msaa: int | None = None,
                           anisotropy: str = DEFAULT_ANISOTROPY):
    """``make(fmt) -> SceneRenderer`` for the window: the scene is loaded and checked now, planned per format."""
    scene = load_scene(path)
    facts = ctx.adapter_facts()
    resolve_plan(scene, facts, msaa=msaa, anisotropy=anisotropy)  # a bad option fails here, cheaply

    def make(fmt: str) -> SceneRenderer:
        # A swapchain image cannot be a storage texture: a compute post path writes it through a scratch copy.
        return SceneRenderer(ctx, scene, resolve_plan(scene, facts, output_format=fmt, msaa=msaa,
                                                      anisotropy=anisotropy, output_storage=False))

    return make
