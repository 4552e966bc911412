"""The overlay inside the demo window: input routed to it first, knob turns re-resolved into a plan, its stats.

A knob turned in the overlay (window/overlay.py) changes the view's LiveKnobs (core/plan/live.py); before the
next frame the window asks :meth:`Settings.replan`: the plan is resolved again through the one resolution
function, and when it equals the current plan nothing is rebuilt; otherwise a new drawable is built from it
with the device's caches kept (post passes' modules, layouts and pipelines, samplers and mip pipelines are
reused; the scene pass's pipelines and the plan's textures are made for the new plan), and one line says
what changed in the plan's words.
"""

from __future__ import annotations

import functools

import wgpu

from wgpurender.core.plan import gpu_memory
from wgpurender.core.plan.live import changed
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.timing import PassTimer
from wgpurender.wgpu_path.window.overlay import Overlay


class Settings:
    """One window's overlay, pass timer and pending knob turns."""

    def __init__(self, ctx: GPUContext, view, fmt: str) -> None:
        self.ctx, self.view, self.fmt = ctx, view, fmt
        self.live = view.start_live()
        self.overlay: Overlay | None = None
        self.timer = PassTimer(ctx)
        self.pending = False

    def attach(self, drawable) -> None:
        """After the first build: the knobs show what the drawable was built with; the overlay is made."""
        plan = getattr(drawable, "plan", None)
        self.live.msaa = plan.msaa if plan is not None else drawable.msaa
        self.overlay = Overlay(self.ctx.device, self.fmt, self.live, self.view.effect_names(), self._turn,
                               scene=plan is not None)
        self._describe(drawable)

    def _turn(self, name: str, value) -> None:
        if name.startswith("effect:"):
            self.live.effects[int(name.split(":")[1])] = value
        else:
            setattr(self.live, name, value)
        self.pending = True

    def replan(self, drawable):
        """(new drawable or None, the line that says what changed). Errors are the caller's to report."""
        self.pending = False
        old = getattr(drawable, "plan", None)
        if old is not None:
            new = self.view.plan(self.fmt)
            if new == old:
                return None, "plan unchanged"
            what = changed(old, new) or ["the plan"]
        else:
            what = [f"msaa {drawable.msaa} -> {self.live.msaa}"]
        candidate = self.view.build(self.fmt, keep_caches=True)
        self._describe(candidate)
        return candidate, "plan: " + "; ".join(what)

    def _describe(self, drawable) -> None:
        plan = getattr(drawable, "plan", None)
        stats = self.overlay.stats
        if plan is not None:
            stats["memory"] = f"{gpu_memory.plan_bytes(plan) / 2**20:.1f} MiB of attachments and readback"
            stats["plan"] = f"{len(plan.passes)} passes, {len(plan.attachments)} attachments, msaa {plan.msaa}"

    # -- a frame ------------------------------------------------------------------------
    def record_fn(self, drawable):
        """The drawable's record with the pass timer where it takes one (scenes: one entry per pass)."""
        if hasattr(drawable, "scene_pass"):
            return functools.partial(drawable.record, timer=self.timer)
        return drawable.record

    def frame_done(self, gpu_ms: dict, frame_ms: float) -> None:
        self.overlay.stats["gpu_ms"] = dict(gpu_ms)
        self.overlay.stats["frame_ms"] = frame_ms

    def draw(self, texture: wgpu.GPUTexture) -> None:
        """The panel over the frame (after its readback), in a pass of its own."""
        encoder = self.ctx.device.create_command_encoder(label="overlay")
        self.overlay.record(encoder, texture)
        self.ctx.queue.submit([encoder.finish()])

    # -- input: the panel first ----------------------------------------------------------
    def mouse_button(self, controls, button: int, action) -> None:
        g = controls.glfw
        if not controls.overlay_shown:  # hidden with F1: every click is the camera's
            controls.mouse_button(button, action)
            return
        if action in (g.PRESS, g.RELEASE):
            self.overlay.mouse_button(button, action == g.PRESS)
        if action == g.PRESS and self.overlay.wants_mouse:
            return
        controls.mouse_button(button, action)

    def cursor_pos(self, controls, x: float, y: float) -> None:
        self.overlay.mouse_pos(x, y)
        controls.cursor_pos(x, y)

    def scroll(self, controls, dy: float) -> None:
        if not controls.overlay_shown or not self.overlay.wants_mouse:
            controls.scroll(dy)
