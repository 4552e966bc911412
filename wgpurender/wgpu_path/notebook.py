"""A stage or a scene outside the window: live in a Jupyter cell with the orbit camera, or frame by frame into a video.

- :class:`Offscreen` draws the demo's drawable (window/view.py: the same stage or scene renderer, the same orbit
  camera) into an offscreen texture and reads it back; :func:`record_frames` turns it into an MP4 or PNG frames
  (core/files/video.py), the camera turning once round a scene over the clip (stages animate with time instead).
- :class:`LiveView` is rendercanvas's Jupyter canvas (a jupyter_rfb widget; rendercanvas comes with wgpu,
  jupyter_rfb is the optional ``notebook`` extra) drawing that drawable on demand, with the demo's mouse and key
  controls (core/view/controls.py, fed browser events). Its display carries a PNG of the first frame beside the
  widget, so a frontend without widgets (nbclient, nbconvert, a notebook viewer) shows the still image.
"""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from wgpurender.core.files.video import FrameWriter
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.core.view.controls import Controls
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.device.targets import create_target
from wgpurender.wgpu_path.window.view import DemoView

FORMAT = "rgba8unorm-srgb"
# The browser's names (KeyboardEvent.key, MouseEvent.button + 1 as rendercanvas numbers them) for what
# core/view/controls.py reads as GLFW's codes.
BROWSER = SimpleNamespace(
    PRESS="down", RELEASE="up", REPEAT="repeat", MOUSE_BUTTON_LEFT=1, MOUSE_BUTTON_RIGHT=2, MOUSE_BUTTON_MIDDLE=3,
    KEY_ESCAPE="Escape", KEY_LEFT="ArrowLeft", KEY_RIGHT="ArrowRight", KEY_UP="ArrowUp", KEY_DOWN="ArrowDown",
    KEY_A="a", KEY_D="d", KEY_W="w", KEY_S="s", KEY_Q="q", KEY_E="e", KEY_R="r", KEY_HOME="Home",
    KEY_F1="F1", KEY_P="p", KEY_EQUAL="=", KEY_KP_ADD="+", KEY_MINUS="-", KEY_KP_SUBTRACT="_",
)
WHEEL_PIXELS_PER_STEP = 100.0  # a browser's wheel notch; one zoom step, as one GLFW scroll unit


class Offscreen:
    """The demo's drawable and orbit camera, drawing into an offscreen ``size`` texture."""

    def __init__(self, ctx: GPUContext, target: str, size: tuple[int, int], msaa: int | None = None,
                 anisotropy: str = DEFAULT_ANISOTROPY) -> None:
        self.ctx, self.size = ctx, size
        self.view = DemoView(ctx, target, msaa, anisotropy)
        self.view.check()
        self.drawable = self.view.build(FORMAT)
        self.texture = create_target(ctx, size, FORMAT)

    @property
    def orbit(self):
        return self.view.orbit

    def draw(self, texture, t: float, read_back: bool) -> np.ndarray | None:
        self.view.apply_camera(self.drawable)
        self.drawable.resize(tuple(texture.size[:2]))
        return run_frame(self.ctx, self.drawable.record, texture, t, read_back=read_back).pixels

    def frame(self, t: float = 0.0) -> np.ndarray:
        return self.draw(self.texture, t, True)


def record_frames(offscreen: Offscreen, out: str | Path, seconds: float, fps: float, turn_degrees: float,
                  progress=None, force: bool = False) -> tuple[Path, int]:
    """Render ``seconds * fps`` frames at t = k / fps, turning the orbit by ``turn_degrees`` over the clip."""
    count = max(1, round(seconds * fps))
    orbit = offscreen.orbit
    yaw = orbit.yaw if orbit is not None else 0.0
    with FrameWriter(out, fps, force) as writer:
        for k in range(count):
            if orbit is not None and turn_degrees:
                orbit.yaw = yaw + math.radians(turn_degrees) * k / count
            writer.write(offscreen.frame(k / fps))
            if progress is not None:
                progress(k + 1, count)
    return writer.path, count


def in_kernel() -> bool:
    """True inside a Jupyter (IPython) kernel, False in a script or a terminal."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and hasattr(shell, "kernel")


def widgets_available() -> bool:
    """True in a Jupyter kernel with jupyter_rfb installed (the frontend may still lack widgets: see LiveView)."""
    if not in_kernel():
        return False
    try:
        import jupyter_rfb  # noqa: F401
    except ImportError:
        return False
    return True


class LiveView:
    """rendercanvas's Jupyter canvas drawing a stage or scene on demand, turned with the mouse and keys."""

    def __init__(self, ctx: GPUContext, target: str, size: tuple[int, int], msaa: int | None = None,
                 anisotropy: str = DEFAULT_ANISOTROPY, still: np.ndarray | None = None) -> None:
        from rendercanvas.jupyter import RenderCanvas

        self.offscreen = Offscreen(ctx, target, size, msaa, anisotropy)
        self.still = self.offscreen.frame(0.0) if still is None else still
        self.fixed_time: float | None = None  # freeze the animation (as demo --time)
        self.canvas = RenderCanvas(size=size, update_mode="ondemand", title=str(Path(target).name))
        self.context = self.canvas.get_context("wgpu")
        self.context.configure(device=ctx.device, format=FORMAT)
        self.controls = Controls(BROWSER, lambda: self.offscreen.orbit)
        self.canvas.add_event_handler(self._on_event, "pointer_down", "pointer_up", "pointer_move", "wheel",
                                      "key_down")
        self.canvas.request_draw(self._draw)

    def _draw(self) -> None:
        t = self.fixed_time if self.fixed_time is not None else self.controls.clock.time()  # P pauses it
        self.offscreen.draw(self.context.get_current_texture(), t, False)

    def _on_event(self, event: dict) -> None:
        kind = event.get("event_type") or event.get("type")
        if kind in ("pointer_down", "pointer_up"):
            self.controls.mouse_button(event.get("button", 1), "down" if kind == "pointer_down" else "up")
            self.controls.cursor_pos(event["x"], event["y"])
        elif kind == "pointer_move":
            self.controls.cursor_pos(event["x"], event["y"])
        elif kind == "wheel":
            self.controls.scroll(-event.get("dy", 0.0) / WHEEL_PIXELS_PER_STEP)
        elif kind == "key_down":
            self.controls.key(event.get("key", ""), "down")
        self.canvas.request_draw()

    def _repr_mimebundle_(self, **kwargs):
        """The widget for a frontend with widgets, and the first frame as PNG for one without."""
        import io

        from PIL import Image as PILImage

        bundle = self.canvas._repr_mimebundle_(**kwargs)
        data, meta = bundle if isinstance(bundle, tuple) else (bundle, {})
        buffer = io.BytesIO()
        PILImage.fromarray(np.ascontiguousarray(self.still)).save(buffer, format="PNG")
        data = {**(data or {}), "image/png": buffer.getvalue()}
        data["text/plain"] = f"LiveView({self.canvas.title!r}): a still frame where widgets are not shown"
        return data, meta
