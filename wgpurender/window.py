"""A GLFW window with a wgpu surface: the course's surface, swapchain and present modes.

vkCreateXlibSurfaceKHR + vkCreateSwapchainKHR become one ``GPUCanvasContext``
configured with a format, a usage and a present mode; vkAcquireNextImageKHR is
``get_current_texture()`` and vkQueuePresentKHR is ``present()``. Resizing
re-configures the surface (the swapchain re-creation of the course), and a
minimised window (0x0 framebuffer) simply renders nothing until it comes back.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import wgpu

from . import slow_frames
from .errors import UserError
from .gpu import GPUContext

PRESENT_MODES = ("fifo", "mailbox", "immediate")
SURFACE_USAGE = wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC | wgpu.TextureUsage.COPY_DST


class Drawable:
    """What the window draws: a stage, or a scene renderer with the same three methods."""

    def resize(self, size: tuple[int, int]) -> None: ...

    def draw(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None: ...


@dataclass
class WindowResult:
    frames: int
    mean_frame_ms: float
    last_frame: np.ndarray | None  # the last presented image, when a screenshot was asked for


def _glfw():
    try:
        import glfw
    except ImportError as err:  # the wheel ships its own libglfw; this is a broken install
        raise UserError(f"cannot import glfw ({err}): pip install glfw, or apt-get install libglfw3") from None
    if not glfw.init():
        raise UserError("GLFW could not open a display: run under a desktop session or Xvfb (DISPLAY must be set)")
    return glfw


def _present_info(glfw, window, present_mode: str) -> dict:
    """The native handles wgpu needs to make a surface, per platform."""
    vsync = present_mode == "fifo"
    if sys.platform.startswith("win"):
        return {"window": int(glfw.get_win32_window(window)), "vsync": vsync}
    if sys.platform.startswith("darwin"):
        return {"window": int(glfw.get_cocoa_window(window)), "vsync": vsync}
    if glfw.get_platform() == glfw.PLATFORM_WAYLAND:
        return {
            "platform": "wayland",
            "window": int(glfw.get_wayland_window(window)),
            "display": int(glfw.get_wayland_display()),
            "vsync": vsync,
        }
    return {
        "platform": "x11",
        "window": int(glfw.get_x11_window(window)),
        "display": int(glfw.get_x11_display()),
        "vsync": vsync,
    }


def surface_format(context, adapter) -> str:
    """An sRGB swapchain format when the surface offers one, as the Vulkan tutorial picks."""
    formats = context._get_capabilities(adapter)["formats"]
    for fmt in formats:
        if fmt.endswith("-srgb"):
            return fmt
    return context.get_preferred_format(adapter)


def set_present_mode(context, adapter, present_mode: str) -> None:
    """Choose the exact present mode (wgpu-py only exposes vsync on/off, so we set the field).

    fifo: wait for vblank, never tears (always available); mailbox: newest frame
    wins at vblank; immediate: no waiting, may tear.
    """
    available = context._get_capabilities(adapter).get("present_modes", ["fifo"])
    if present_mode not in available:
        raise UserError(
            f"present mode {present_mode!r} is not offered by this surface: available: {', '.join(available)}"
        )
    from wgpu.backends.wgpu_native._ffi import lib

    context._wgpu_config.presentMode = getattr(lib, f"WGPUPresentMode_{present_mode.capitalize()}")
    context._configure_screen_real()


def run_window(
    ctx: GPUContext,
    make_drawable: Callable[[str], Drawable],
    *,
    title: str = "wgpurender",
    size: tuple[int, int] = (800, 600),
    frames: int | None = None,
    present_mode: str = "fifo",
    fixed_time: float | None = None,
    screenshot: bool = False,
) -> WindowResult:
    """Open a window and draw until it closes (Esc, close button) or ``frames`` frames were shown.

    ``make_drawable(format)`` builds the stage for the surface's format.
    """
    if present_mode not in PRESENT_MODES:
        raise UserError(f"unknown present mode {present_mode!r}: choose one of {', '.join(PRESENT_MODES)}")
    glfw = _glfw()
    glfw.window_hint(glfw.CLIENT_API, glfw.NO_API)  # wgpu owns the surface, GLFW makes no GL context
    window = glfw.create_window(size[0], size[1], title, None, None)
    if not window:
        glfw.terminate()
        raise UserError("GLFW could not create a window")
    try:
        return _loop(ctx, glfw, window, make_drawable, frames, present_mode, fixed_time, screenshot)
    finally:
        glfw.destroy_window(window)
        glfw.terminate()


def _loop(ctx, glfw, window, make_drawable, frames, present_mode, fixed_time, screenshot) -> WindowResult:
    from .targets import read_texture

    glfw.set_key_callback(window, lambda w, key, *_: key == glfw.KEY_ESCAPE and glfw.set_window_should_close(w, True))
    context = wgpu.gpu.get_canvas_context(_present_info(glfw, window, present_mode))
    fmt = surface_format(context, ctx.adapter)
    context.set_physical_size(*glfw.get_framebuffer_size(window))
    context.configure(device=ctx.device, format=fmt, usage=SURFACE_USAGE)
    set_present_mode(context, ctx.adapter, present_mode)
    drawable = make_drawable(fmt)
    start, shown, last = time.perf_counter(), 0, None
    while not glfw.window_should_close(window) and (frames is None or shown < frames):
        glfw.poll_events()
        width, height = glfw.get_framebuffer_size(window)
        if width == 0 or height == 0:  # minimised: nothing to draw into, wait for the next event
            glfw.wait_events_timeout(0.1)
            continue
        context.set_physical_size(width, height)
        texture = context.get_current_texture()
        drawable.resize((width, height))
        encoder = ctx.device.create_command_encoder(label="frame")
        t = fixed_time if fixed_time is not None else time.perf_counter() - start
        drawable.record(encoder, texture, t)
        ctx.queue.submit([encoder.finish()])
        if screenshot and (frames is None or shown == frames - 1):
            last = read_texture(ctx, texture)  # a copy of what we rendered, before it is presented
        context.present()
        shown += 1
        slow_frames.tick(ctx, drawable, (width, height))  # a frame over 3 s says once why (reliab, issue 15)
    elapsed = (time.perf_counter() - start) * 1e3
    if screenshot and last is None and shown:
        raise UserError("the window closed before a frame could be captured")
    return WindowResult(frames=shown, mean_frame_ms=elapsed / max(shown, 1), last_frame=last)
