"""A GLFW window with a wgpu surface: the course's surface, swapchain and present modes, plus the demo's controls.

vkCreateXlibSurfaceKHR + vkCreateSwapchainKHR become one ``GPUCanvasContext`` made from
the native window handles (``wgpu.utils.get_glfw_present_info``) and configured with a
format and a usage; vkAcquireNextImageKHR is ``get_current_texture()`` and vkQueuePresentKHR
is ``present()``. Resizing re-configures the surface (the swapchain re-creation of the
course), a minimised window (0x0 framebuffer) renders nothing until it comes back, and an
occluded one (``wgpu.DrawCancelled`` from ``get_current_texture()``, wgpu-py 0.32) skips
the frame, like VK_ERROR_OUT_OF_DATE_KHR / VK_SUBOPTIMAL_KHR in the course.

Present modes: wgpu-py 0.32's public API has vsync on or off, nothing finer. ``fifo``
(vsync on, never tears, always offered) and ``immediate`` (vsync off: wgpu takes immediate,
else mailbox, else fifo, whichever the surface offers first) map onto it; ``mailbox`` cannot
be asked for without reaching into the context's private configuration, so it is not offered.

The demo on top (wgpurender/cli/demo.py), one module each in this package: ``view`` (what is
shown: a stage or a scene, rebuilt from its files, with the orbit camera of wgpurender/core/view/orbit.py),
``live_reload`` (which files changed; a broken file leaves the last good pipeline on screen and
prints ``file:line: message`` once). Shared with the raw-Vulkan window (raw_path/window/__init__.py), from the
core: ``core/view/controls.py`` (mouse and keys, and the tests' synthetic input) and ``core/view/frame_times.py``
(FPS and frame time in the title, the benchmark mode).
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import wgpu

from wgpurender.core.errors import UserError
from wgpurender.core.view import garbage, slow_frames
from wgpurender.core.view.controls import Controls, PausableClock, ScriptEvent, due, install_callbacks, send
from wgpurender.core.view.frame_times import BenchmarkSpec, FrameRecorder, TitleCounter
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.window.live_reload import FileWatcher, error_line
from wgpurender.wgpu_path.window.view import DemoView

PRESENT_MODES = ("fifo", "immediate")
SURFACE_USAGE = wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC
RELOAD_POLL_S = 0.25  # how often the watched files are stat'ed
WAIT_RELOAD_TIMEOUT_S = 60.0
# Errors a rebuild or a new drawable's first frame can raise when a file is broken.
REBUILD_ERRORS = (UserError, wgpu.GPUError, ValueError, KeyError, TypeError, OSError)


@dataclass
class WindowResult:
    frames: int
    mean_frame_ms: float
    last_frame: np.ndarray | None  # the last presented image, when a screenshot was asked for
    reload_errors: list[str] = field(default_factory=list)
    benchmark: FrameRecorder | None = None


def _glfw():
    try:
        import glfw
    except ImportError as err:  # the wheel ships its own libglfw; this is a broken install
        raise UserError(f"cannot import glfw ({err}): pip install glfw, or apt-get install libglfw3") from None
    if not glfw.init():
        raise UserError("GLFW could not open a display: run under a desktop session or Xvfb (DISPLAY must be set)")
    return glfw


def present_info(window, present_mode: str) -> dict:
    """The native handles wgpu needs to make a surface, from wgpu's own helper; vsync picks the present mode."""
    from wgpu.utils.glfw_present_info import get_glfw_present_info

    if present_mode == "mailbox":
        raise UserError("present mode 'mailbox' is not offered through wgpu-py 0.32's public API (vsync on or off "
                        "only): use fifo (vsync) or immediate (no vsync; wgpu falls back to mailbox where immediate "
                        "is missing)")
    if present_mode not in PRESENT_MODES:
        raise UserError(f"unknown present mode {present_mode!r}: choose one of {', '.join(PRESENT_MODES)}")
    return get_glfw_present_info(window, vsync=present_mode == "fifo")


def surface_format(context, adapter) -> str:
    """The sRGB variant of the surface's preferred format, as the Vulkan tutorial picks (B8G8R8A8_SRGB)."""
    from wgpurender.wgpu_path.device.native import surface_supports

    preferred = context.get_preferred_format(adapter)
    if not surface_supports(context, adapter):
        backend = adapter.info["backend_type"]
        raise UserError(f"this window cannot show {backend} frames: wgpu-native says the window's surface does not "
                        f"support the {backend} adapter; use --backend vulkan, or render headless "
                        "(wgpurender render --backend opengl)")
    return preferred if preferred.endswith("-srgb") else preferred + "-srgb"


def run_window(
    ctx: GPUContext,
    view: DemoView,
    *,
    title: str = "wgpurender",
    size: tuple[int, int] = (800, 600),
    frames: int | None = None,
    present_mode: str = "fifo",
    fixed_time: float | None = None,
    screenshot: bool = False,
    benchmark: BenchmarkSpec | None = None,
    script: list[ScriptEvent] = (),
    video=None,
    overlay: bool = False,
) -> WindowResult:
    """Open a window and draw ``view`` until it closes (Esc, close button), ``frames`` frames were shown,
    or the benchmark's run time is over. ``video``: a core.files.video.FrameWriter that gets every presented frame.
    ``overlay``: the settings overlay (window/overlay.py; the CLI's default, --no-overlay hides it)."""
    glfw = _glfw()
    glfw.window_hint(glfw.CLIENT_API, glfw.NO_API)  # wgpu owns the surface, GLFW makes no GL context
    window = glfw.create_window(size[0], size[1], title, None, None)
    if not window:
        glfw.terminate()
        raise UserError("GLFW could not create a window")
    demo = None
    try:
        demo = DemoWindow(ctx, glfw, window, view, title, present_mode, overlay)
        return demo.run(frames, fixed_time, screenshot, benchmark, list(script), video)
    finally:
        if demo is not None:
            demo.close()  # the surface goes before its window: released after it, it crashes the process
        del demo
        glfw.destroy_window(window)
        glfw.terminate()


class DemoWindow:
    """One window's state: surface, drawable (and the last good one), controls, watcher, title counters."""

    def __init__(self, ctx: GPUContext, glfw, window, view: DemoView, title: str, present_mode: str,
                 overlay: bool = False) -> None:
        self.ctx, self.glfw, self.window, self.view, self.title = ctx, glfw, window, view, title
        self.context = wgpu.gpu.get_canvas_context(present_info(window, present_mode))
        self.format = surface_format(self.context, ctx.adapter)
        self.context.set_physical_size(*glfw.get_framebuffer_size(window))
        self.context.configure(device=ctx.device, format=self.format, usage=SURFACE_USAGE)
        self.controls = Controls(glfw, lambda: view.orbit)
        self.settings = self._settings(overlay)
        self._install_callbacks()
        self.drawable = view.build(self.format)  # a broken file at start-up is the user's error: exit 2
        if self.settings is not None:
            self.settings.attach(self.drawable)
        self.first_frame_pending = True
        self.watcher = FileWatcher(view.watched)
        self.previous = None  # the last good drawable while a rebuilt one has not drawn its first frame
        self.reload_errors: list[str] = []
        self.broken = False  # the files as they are now do not build: the title says so
        self.reloads = 0
        self._last_poll = time.perf_counter()
        self.titles = TitleCounter(title)

    def _settings(self, overlay: bool):
        if not overlay:
            return None
        from wgpurender.wgpu_path.window.overlay import available

        missing = available()
        if missing:
            print(missing, file=sys.stderr, flush=True)
            return None
        from wgpurender.wgpu_path.window.settings import Settings

        return Settings(self.ctx, self.view, self.format)

    def _install_callbacks(self) -> None:
        """GLFW's input to the controls, through the overlay first when there is one."""
        g, c, s = self.glfw, self.controls, self.settings
        if s is None:
            install_callbacks(g, self.window, c)
            return
        g.set_key_callback(self.window, lambda _w, key, _sc, action, _mods: c.key(key, action))
        g.set_mouse_button_callback(self.window, lambda _w, button, action, _mods: s.mouse_button(c, button, action))
        g.set_cursor_pos_callback(self.window, lambda _w, x, y: s.cursor_pos(c, x, y))
        g.set_scroll_callback(self.window, lambda _w, _dx, dy: s.scroll(c, dy))

    def close(self) -> None:
        """Release the surface (vkDestroySwapchainKHR + vkDestroySurfaceKHR) while the window still exists."""
        self.drawable = self.previous = None
        if self.context is not None:
            self.context.unconfigure()
            self.context = None

    # -- live reload -----------------------------------------------------------------
    def poll_files(self, force: bool = False) -> bool:
        """Rebuild when a watched file changed; True when a rebuild was tried."""
        now = time.perf_counter()
        if not force and now - self._last_poll < RELOAD_POLL_S:
            return False
        self._last_poll = now
        changed = self.watcher.changed()
        if not changed:
            return False
        self.reloads += 1
        names = ", ".join(p.name for p in changed)
        try:
            candidate = self.view.build(self.format)
        except REBUILD_ERRORS as err:
            self._report(err)
        else:
            self.previous, self.drawable = self.drawable, candidate
            self.first_frame_pending = True
            print(f"reloaded after a change to {names}", flush=True)
        self.watcher = FileWatcher(self.view.watched | set(self.watcher.paths))
        return True

    def _report(self, err: BaseException) -> None:
        """Print a failed rebuild once (the watcher only fires again when a file changes again)."""
        line = error_line(err, self.view.watched | set(self.watcher.paths))
        self.reload_errors.append(line)
        self.broken = True
        print(f"reload failed, still showing the last good frame: {line}", file=sys.stderr, flush=True)

    # -- a frame ----------------------------------------------------------------------
    def _run_frame(self, texture, t: float, capture: bool):
        """One frame through the shared frame loop (wgpurender/wgpu_path/device/frame_loop.py) into the swapchain image.

        A rebuilt drawable's first frame may still fail (pipelines made on first use); then the last
        good drawable draws this frame and stays, and the error is printed once.
        """
        from wgpurender.wgpu_path.device.frame_loop import run_frame

        while True:
            if hasattr(self.drawable, "play"):  # a scene: its glTF animations at this frame's time (stages: none)
                self.drawable.play(t)
                self.view.follow(self.drawable)  # an animated file camera takes the orbit with it
            self.view.apply_camera(self.drawable)
            self.drawable.resize(tuple(texture.size[:2]))
            record, timer = self._record_fn()
            if not self.first_frame_pending:
                return run_frame(self.ctx, record, texture, t, read_back=capture, timer=timer)
            try:
                with self.view.record_lazy_loads():  # pipelines made in the first frame load shaders too
                    frame = run_frame(self.ctx, record, texture, t, read_back=capture, timer=timer)
            except REBUILD_ERRORS as err:
                if self.previous is None:
                    raise
                self._report(err)
                self.drawable, self.previous, self.first_frame_pending = self.previous, None, False
                continue
            self.first_frame_pending, self.previous, self.broken = False, None, False
            self.watcher = FileWatcher(self.view.watched | set(self.watcher.paths))
            garbage.settle()  # the load's objects frozen: no collection during the frames walks them again
            return frame

    def _record_fn(self):
        if self.settings is None:
            return self.drawable.record, None
        return self.settings.record_fn(self.drawable), self.settings.timer

    def frame(self, t: float, capture: bool) -> tuple[bool, np.ndarray | None]:
        """Draw and present one frame: (drawn, pixels when ``capture``). False: nothing to draw into."""
        width, height = self.glfw.get_framebuffer_size(self.window)
        if width == 0 or height == 0:  # minimised: nothing to draw into, wait for the next event
            self.glfw.wait_events_timeout(0.1)
            return False, None
        self.context.set_physical_size(width, height)
        try:
            texture = self.context.get_current_texture()
        except wgpu.DrawCancelled:  # occluded (or the surface is being re-made): skip this frame
            self.glfw.wait_events_timeout(0.05)
            return False, None
        frame = self._run_frame(texture, t, capture)  # read back before present hands the image away
        if self.settings is not None:  # the panel goes over the frame after its readback: shots are the scene
            self.settings.frame_done(frame.gpu_ms, frame.frame_ms)
            if self.controls.overlay_shown:  # F1 hides it
                self.settings.draw(texture)
        self.context.present()
        return True, frame.pixels

    def _update_title(self, now: float) -> None:
        status = "  |  reload failed (see the terminal)" if self.broken else ""
        title = self.titles.frame_done(now, status)
        if title is not None:
            self.glfw.set_window_title(self.window, title)

    # -- the loop -----------------------------------------------------------------------
    def run(self, frames, fixed_time, screenshot, benchmark, script, video=None) -> WindowResult:
        recorder = FrameRecorder(benchmark) if benchmark else None
        start, shown, last = time.perf_counter(), 0, None
        self.controls.clock = PausableClock()  # P pauses it
        while not self.glfw.window_should_close(self.window) and (frames is None or shown < frames):
            self.glfw.poll_events()
            shots = self._run_script(script, shown)
            if self.controls.close_requested:
                break
            if self.settings is not None and self.settings.pending:
                self._replan()
            self.poll_files()
            t = fixed_time if fixed_time is not None else self.controls.clock.time()
            want = bool(shots) or video is not None or (screenshot and (frames is None or shown == frames - 1))
            drawn, pixels = self.frame(t, want)
            if not drawn:
                continue
            if video is not None:
                video.write(pixels)
            for path in shots:
                from wgpurender.core.files.imageio import save_png

                save_png(path, pixels)
            if screenshot and pixels is not None:
                last = pixels
            shown += 1
            size = tuple(self.glfw.get_framebuffer_size(self.window))
            slow_frames.tick(self.ctx, self.drawable, size)  # a frame over 3 s says once why (issue 15)
            now = time.perf_counter()
            self._update_title(now)
            if recorder is not None:
                recorder.frame_done(now)
                if recorder.finished():
                    break
        elapsed = (time.perf_counter() - start) * 1e3
        if screenshot and last is None and shown:
            raise UserError("the window closed before a frame could be captured")
        return WindowResult(frames=shown, mean_frame_ms=elapsed / max(shown, 1), last_frame=last,
                            reload_errors=self.reload_errors, benchmark=recorder)

    def _replan(self) -> None:
        """A knob was turned: the plan re-resolved, the drawable rebuilt only if the plan changed."""
        try:
            candidate, line = self.settings.replan(self.drawable)
        except REBUILD_ERRORS as err:
            print(f"knob not applied: {str(err).splitlines()[0]}", file=sys.stderr, flush=True)
            return
        if candidate is not None:
            self.previous, self.drawable = self.drawable, candidate
            self.first_frame_pending = True
        print(line, flush=True)

    def _send(self, event: ScriptEvent, script: list[ScriptEvent]) -> None:
        """A script event as GLFW would deliver it (through the overlay when there is one); ``click NAME`` moves
        to the overlay's widget NAME and presses there, releasing on the next frame."""
        if self.settings is None:
            if event.action == "click":
                raise UserError("--test-input click: there is no overlay (imgui-bundle missing, or --no-overlay)")
            send(self.controls, event)
            return
        g, c, s = self.glfw, self.controls, self.settings
        button = g.MOUSE_BUTTON_RIGHT if event.args[:1] == ("right",) else g.MOUSE_BUTTON_LEFT
        if event.action == "click":
            if event.args[0] not in s.overlay.rects:
                raise UserError(f"--test-input click: no overlay widget {event.args[0]!r}; there are: "
                                f"{', '.join(sorted(s.overlay.rects))}")
            s.cursor_pos(c, *s.overlay.rects[event.args[0]])
            s.mouse_button(c, g.MOUSE_BUTTON_LEFT, g.PRESS)
            script.insert(0, ScriptEvent(event.frame + 1, "release", ()))
        elif event.action in ("press", "release"):
            s.mouse_button(c, button, g.PRESS if event.action == "press" else g.RELEASE)
        elif event.action == "move":
            s.cursor_pos(c, float(event.args[0]), float(event.args[1]))
        elif event.action == "scroll":
            s.scroll(c, float(event.args[0]))
        else:
            send(c, event)

    def _run_script(self, script: list[ScriptEvent], frame: int) -> list[Path]:
        """Deliver the test script's events for this frame; the paths of shots to save after it."""
        shots = []
        for event in due(script, frame):
            if event.action == "shot":
                shots.append(Path(event.args[0]))
            elif event.action == "wait-reload":
                self._wait_reload()
            else:
                self._send(event, script)
        return shots

    def _wait_reload(self) -> None:
        deadline = time.perf_counter() + WAIT_RELOAD_TIMEOUT_S
        while not self.poll_files(force=True):
            if time.perf_counter() > deadline:
                raise UserError(f"--test-input wait-reload: no watched file changed in {WAIT_RELOAD_TIMEOUT_S:.0f} s")
            self.glfw.poll_events()
            time.sleep(0.05)
