"""The Python API: render a course stage or a scene file, render it again on the raw-Vulkan path, compare.

For scripts and notebooks::

    import wgpurender as w

    img = w.render("triangle", size=(320, 240))          # the wgpu path
    ref = w.reference("triangle", size=(320, 240))       # the raw-Vulkan path (needs glslc)
    print(w.compare(ref, img))                           # PSNR, max difference, FLIP ...
    w.side_by_side(img, ref, w.heatmap(ref, img))        # shown inline by Jupyter
    img.save("triangle.png")
    w.show("final")                                      # live in Jupyter, the orbit camera (a still elsewhere)
    w.record("3d", "cubes.mp4", seconds=2)               # MP4 (imageio-ffmpeg) or a folder of PNG frames

A target is a stage name (``wgpurender stages`` lists them, :func:`stage_names` returns them) or a
scene file (``*.toml``). Every call returns an :class:`Image`: ``.pixels`` (numpy, ``(H, W, 4)``),
``.save(path)``, ``.timings``, ``.plan`` (the render plan a scene was drawn from, on either path) and a
PNG representation for Jupyter. Bad input raises :class:`wgpurender.UserError` with a message that
says how to fix it (the CLI prints the same message).

One GPU context serves every call in a process (:func:`wgpurender.wgpu_path.device.context.get_context` keeps it), so
the adapter and device are made once. The functions are thread-safe: calls that use the GPU hold one lock,
so threads take turns on the device (compare and heatmap, numpy only, run side by side). Nothing here imports
wgpu, vulkan or trimesh until a render needs them: ``import wgpurender`` stays cheap.
"""

from __future__ import annotations

import functools
import io
import os
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from wgpurender.core import checks
from wgpurender.core.errors import UserError
from wgpurender.core.plan.anisotropy import ANISOTROPY_RULES, DEFAULT_ANISOTROPY

if TYPE_CHECKING:  # pragma: no cover
    from wgpurender.core.plan import RenderPlan
    from wgpurender.core.verdict.compare import Comparison

Size = tuple[int, int] | str | None
Target = str | os.PathLike
# One lock around every use of the process's GPU contexts (wgpu's device, the raw path's Vulkan device): a device
# used from two threads mid-frame aborted the process in wgpu-native, and the frame loop's one readback buffer
# per context handed a call another call's image. Reentrant: record/show render through the same functions.
_GPU = threading.RLock()


def _one_at_a_time(function):
    """Run ``function`` holding the API's GPU lock: thread-safe calls, one at a time on the device."""

    @functools.wraps(function)
    def locked(*args, **kwargs):
        with _GPU:
            return function(*args, **kwargs)

    return locked


@dataclass
class Image:
    """One rendered (or derived) image.

    ``pixels``: ``(H, W, 4)`` numpy array; uint8 for the 8-bit formats (the stored bytes, so
    sRGB-encoded for ``rgba8unorm-srgb``), float16 for ``rgba16float`` (linear).
    ``path``: ``"wgpu"``, ``"raw"`` (the raw-Vulkan reference) or ``"derived"`` (heatmap, montage).
    ``timings``: milliseconds; ``call_ms`` is the whole call (set-up included), ``frame_ms`` one
    steady-state frame (wgpu path only: record, submit, GPU work, read back).
    ``plan``: the :class:`~wgpurender.core.plan.RenderPlan` a scene was drawn from (either path), else None.
    """

    pixels: np.ndarray
    target: str
    path: str
    timings: dict[str, float] = field(default_factory=dict)
    adapter: str = ""
    plan: RenderPlan | None = None

    @property
    def size(self) -> tuple[int, int]:
        """(width, height)."""
        return int(self.pixels.shape[1]), int(self.pixels.shape[0])

    def rgba8(self) -> np.ndarray:
        """The pixels as 8-bit sRGB-encoded RGBA (float pixels are linear and get encoded)."""
        from wgpurender.core.files.imageio import to_uint8

        return to_uint8(np.ascontiguousarray(self.pixels))

    def save(self, path: str | os.PathLike) -> Path:
        """Write the image atomically; the format follows the suffix (see :func:`core.files.imageio.save_image`)."""
        from wgpurender.core.files.imageio import save_image

        return save_image(path, self.pixels)

    def _repr_png_(self) -> bytes:
        """PNG bytes: Jupyter shows the image inline."""
        from PIL import Image as PILImage

        buffer = io.BytesIO()
        PILImage.fromarray(self.rgba8()).save(buffer, format="PNG")
        return buffer.getvalue()

    def __repr__(self) -> str:
        w, h = self.size
        frame = self.timings.get("frame_ms")
        timing = f", frame {frame:.2f} ms" if frame is not None else ""
        return f"<wgpurender.Image {self.target!r} ({self.path}) {w}x{h} {self.pixels.dtype}{timing}>"


def _size(size: Size) -> tuple[int, int] | None:
    return checks.size(size)


def _target(target: Target) -> str:
    if not isinstance(target, (str, os.PathLike)) or not str(target):
        raise UserError(f"target must be a stage name or a scene file path, got {type(target).__name__} "
                        f"{target!r}; wgpurender.stage_names() lists the stages")
    return str(target)


@_one_at_a_time
def render(target: Target, size: Size = None, msaa: int | None = None, format: str | None = None,
           backend: str | None = None, t: float = 0.0, anisotropy: str = DEFAULT_ANISOTROPY,
           camera: int | None = None, **knobs) -> Image:
    """Render a stage or a scene file on the wgpu path, headless.

    ``size``: ``(width, height)`` or ``"WxH"`` (default 800x600 for a stage, the scene's
    ``[render] size`` for a scene); ``msaa``: 1 or 4 (default: the stage's or the scene's);
    ``format``: ``rgba8unorm-srgb``, ``rgba8unorm`` or ``rgba16float``; ``backend``: ``vulkan``
    (default), ``opengl``, ``metal``, ``d3d12`` or ``auto`` (docs/backends.md); ``t``: animation time in seconds
    (a stage's; a scene's glTF models with animations are posed at it, overriding their model blocks' ``time``,
    and a scene without one refuses a time other than 0);
    ``anisotropy`` (scenes): ``"auto"`` (the scene's on a GPU, 1 on a CPU adapter) or ``"scene"``; ``knobs``
    (scenes): the plan's other knobs, e.g. ``post_path="compute"``, ``post_fuse=False``, ``immediates="off"``,
    ``reverse_z=True`` (:data:`wgpurender.core.plan.KNOB_FLAGS`); ``camera`` (scenes): view through camera K of
    the scene's glTF model instead of its ``[camera]`` (``--camera K``). A scene is drawn from
    :func:`plan`'s plan for the adapter used, and ``Image.plan`` is that plan (what :func:`explain` prints).
    ``wgpurender render`` calls this function, so the CLI's image is this image.
    """
    start = time.perf_counter()
    backend = checks.backend(backend)
    from wgpurender.wgpu_path.device import driver_preload

    driver_preload.start(backend)  # the drivers' libraries load while wgpu-py is imported (issue 31.5)
    from wgpurender.wgpu_path.device.context import get_context, start_context

    target, wh, msaa, format, t = _target(target), _size(size), checks.msaa(msaa), checks.output_format(format), \
        checks.time(t)
    anisotropy = checks.choice(anisotropy, "anisotropy", ANISOTROPY_RULES)
    knobs = _with_camera(knobs, camera)
    scene = _is_scene(target, anisotropy, knobs)
    start_context(backend)  # the device is made on a thread while the renderer is imported (issue 31.5)
    if scene:
        from wgpurender.wgpu_path.scene import render_plan

        ctx = get_context(backend)
        result = render_plan(ctx, _wgpu_plan(ctx, target, wh, msaa, format, anisotropy, {**knobs, "time": t}), t)
    else:
        from wgpurender.wgpu_path.render import render_stage

        ctx = get_context(backend)
        result = render_stage(str(target), wh or (800, 600), format, msaa, t, ctx)
    timings = {"frame_ms": result.frame_ms, "call_ms": (time.perf_counter() - start) * 1e3}
    return Image(result.pixels, str(target), "wgpu", timings, result.adapter, result.plan)


@_one_at_a_time
def export(target: Target, out: str | os.PathLike, size: Size = "800x600", force: bool = False) -> Path:
    """Write a static page into folder ``out`` that renders the stage or scene live with the browser's WebGPU
    (what ``wgpurender export`` does; docs/backends.md). Returns the page's path (``out/index.html``).
    ``out``: new, empty, or an earlier output (only the files wgpurender wrote there are replaced);
    ``force=True`` writes into a non-empty folder that holds no earlier output, beside its files."""
    from wgpurender.webpage import export as write_page

    target, out, wh, force = _target(target), checks.output_path(out, "out"), _size(size), checks.flag(force, "force")
    return write_page(target, out, wh or (800, 600), force).page


@_one_at_a_time
def reference(target: Target, size: Size = None, msaa: int | None = None, format: str | None = None,
              t: float = 0.0, anisotropy: str = DEFAULT_ANISOTROPY, camera: int | None = None, **knobs) -> Image:
    """Render a stage or a scene file on the raw-Vulkan reference path (the ``vulkan`` binding and GLSL).

    Same arguments as :func:`render` (no ``backend``: this path is Vulkan). A scene's plan is resolved by the
    same function for the raw path's device (``Image.plan``), so on one device both paths draw one plan.
    Needs ``glslc`` on PATH the first time a shader is compiled (the SPIR-V is cached in ~/.cache/wgpurender).
    """
    from wgpurender.raw_path.device.context import get_vulkan

    start = time.perf_counter()
    target, wh, msaa, format, t = _target(target), _size(size), checks.msaa(msaa), checks.output_format(format), \
        checks.time(t)
    anisotropy = checks.choice(anisotropy, "anisotropy", ANISOTROPY_RULES)
    knobs = _with_camera(knobs, camera)
    plan = None
    if _is_scene(target, anisotropy, knobs):
        from wgpurender.core.plan import resolve_plan
        from wgpurender.raw_path.scene import render_scene_plan

        plan = resolve_plan(target, get_vulkan().adapter_facts(), size=wh, output_format=format, msaa=msaa,
                            anisotropy=anisotropy, time=t, **knobs)
        pixels = render_scene_plan(plan, t)
    else:
        from wgpurender.raw_path import render_reference

        pixels = render_reference(target, size=wh, fmt=format, msaa=msaa, t=t)
    timings = {"call_ms": (time.perf_counter() - start) * 1e3}
    return Image(pixels, str(target), "raw", timings, get_vulkan().describe(), plan)


def _with_camera(knobs: dict, camera: int | None) -> dict:
    """The plan's flags with ``camera`` (a file camera's index) among them when it is given: resolve_plan takes
    it, and a stage, which has no plan, refuses it with the knobs."""
    if camera is None:
        return knobs
    return {**knobs, "camera": checks.integer(camera, "camera", 0, 2**31 - 1)}


def _is_scene(target: str, anisotropy: str, knobs: dict) -> bool:
    """Whether ``target`` is a scene file; a stage with plan knobs, or an anisotropy rule other than the default,
    is refused (a stage has no plan and its samplers are its own: they apply to scenes), not ignored."""
    from wgpurender.core.course.formats import is_scene_file
    from wgpurender.core.plan.anisotropy import check_applies

    if is_scene_file(target):
        return True  # a time poses the scene's animated glTF models (resolve_plan), or is refused there
    check_applies(target, False, anisotropy)
    if knobs:
        raise UserError(f"plan knob {sorted(knobs)[0]!r} applies to scene files: stage {target!r} has no plan")
    return False


def check_static(target: str, t: float | None) -> None:
    """The window plays a scene's glTF animations from its clock; ``--time T`` freezes them at T. On a scene
    without any (nothing would change) a time other than 0 is refused in one line."""
    if not t:
        return
    from wgpurender.core.scene import load_scene
    from wgpurender.core.scene.playback import tracks

    if not tracks(load_scene(target)):
        raise UserError(f"scene {str(target)!r} is static: none of its models is a glTF file with an animation, so "
                        f"--time {t:g} would change nothing (it freezes a stage's or a glTF animation; leave it out)")


def _wgpu_plan(ctx, scene: Target, size, msaa, format, anisotropy, knobs: dict) -> RenderPlan:
    """The one plan (core/plan/resolve.py) for the wgpu path on ``ctx``'s adapter (None: no adapter)."""
    from wgpurender.core.plan import resolve_plan

    facts = ctx.adapter_facts() if ctx is not None else None
    return resolve_plan(scene, facts, size=size, output_format=format, msaa=msaa, anisotropy=anisotropy, **knobs)


def _pixels(image: Image | np.ndarray | str | os.PathLike, name: str) -> np.ndarray:
    """8-bit pixels from an Image, an array (float = linear) or an image file."""
    from wgpurender.core.files.imageio import load_png

    if isinstance(image, Image):
        return image.rgba8()
    if isinstance(image, (str, os.PathLike)):
        return load_png(image)
    if isinstance(image, np.ndarray):
        return checks.image_array(image, name)
    raise UserError(f"{name}: expected a wgpurender.Image, a numpy array or an image path, got {type(image).__name__}")


def compare(a: Image | np.ndarray | str | os.PathLike, b: Image | np.ndarray | str | os.PathLike, *,
            flip: bool = True) -> Comparison:
    """How far image ``b`` is from the reference ``a``: PSNR, largest channel difference, shares of
    pixels off by more than 1/255 and 2/255, mean FLIP (``flip=False`` skips it: NaN).

    Returns a :class:`~wgpurender.core.verdict.compare.Comparison`; ``.as_dict()`` gives plain numbers,
    ``.summary()`` one line.
    """
    from wgpurender.core.verdict.compare import compare_images

    if not isinstance(flip, (bool, np.bool_)):
        raise UserError(f"flip must be True or False, got {type(flip).__name__} {flip!r}")
    return compare_images(_pixels(a, "a"), _pixels(b, "b"), with_flip=bool(flip))


def heatmap(a: Image | np.ndarray | str | os.PathLike, b: Image | np.ndarray | str | os.PathLike,
            gain: float = 32.0) -> Image:
    """Where ``a`` and ``b`` differ, magnified by ``gain``, with its colour scale drawn below."""
    from wgpurender.core.verdict.compare import heatmap_with_scale

    gain = checks.gain(gain)
    return Image(heatmap_with_scale(_pixels(a, "a"), _pixels(b, "b"), gain), "heatmap", "derived")


def side_by_side(*images: Image | np.ndarray, gap: int = 4) -> Image:
    """Images in one row (aligned at the top, ``gap`` pixels apart): wgpu beside raw beside the heatmap."""
    if not images:
        raise UserError("side_by_side needs at least one image")
    gap = checks.gap(gap)
    parts = [_pixels(i, f"image {n}") for n, i in enumerate(images)]
    parts = [np.dstack([p, np.full(p.shape[:2], 255, np.uint8)]) if p.shape[2] == 3 else p for p in parts]
    height = max(p.shape[0] for p in parts)
    width = sum(p.shape[1] for p in parts) + gap * (len(parts) - 1)
    out = np.zeros((height, width, 4), np.uint8)
    out[..., 3] = 255
    x = 0
    for p in parts:
        out[: p.shape[0], x : x + p.shape[1]] = p
        x += p.shape[1] + gap
    return Image(out, " | ".join(getattr(i, "target", "array") for i in images), "derived")


@_one_at_a_time
def plan(scene: Target, size: Size = None, msaa: int | None = None, format: str | None = None,
         backend: str | None = None, anisotropy: str = DEFAULT_ANISOTROPY, camera: int | None = None,
         t: float = 0.0, **knobs) -> RenderPlan:
    """The render plan :func:`render` draws for a scene file on this machine's adapter (its "auto" knobs
    decided for it by :func:`wgpurender.core.plan.resolve_plan`); with no usable adapter, the plan with those
    knobs left open (it says so)."""
    from wgpurender.core.course.formats import is_scene_file

    scene, size, msaa, format = _target(scene), _size(size), checks.msaa(msaa), checks.output_format(format)
    anisotropy = checks.choice(anisotropy, "anisotropy", ANISOTROPY_RULES)
    if not is_scene_file(scene):
        raise UserError(f"a plan needs a scene file (.toml), got stage {str(scene)!r}")
    knobs = {**_with_camera(knobs, camera), "time": checks.time(t)}
    return _wgpu_plan(_context_or_none(checks.backend(backend)), scene, size, msaa, format, anisotropy, knobs)


def explain(scene: Target, size: Size = None, msaa: int | None = None, format: str | None = None,
            backend: str | None = None, anisotropy: str = DEFAULT_ANISOTROPY, camera: int | None = None,
            t: float = 0.0, **knobs) -> str:
    """The render plan of a scene file as text (what ``wgpurender render SCENE --explain`` prints): :func:`plan`'s."""
    return plan(scene, size, msaa, format, backend, anisotropy, camera, t, **knobs).explain()


def _context_or_none(backend: str | None):
    """The wgpu context :func:`render` would use, or None when there is none (the plan is still printable)."""
    from wgpurender.wgpu_path.device.context import get_context

    try:
        return get_context(backend)
    except UserError:
        return None


def stage_names() -> list[str]:
    """The wgpu path's stage names, in course order."""
    from wgpurender.wgpu_path.stages import all_stages

    return list(all_stages())


def reference_stage_names() -> list[str]:
    """The stages the raw-Vulkan path can render, in course order."""
    from wgpurender.raw_path import reference_stage_names

    return reference_stage_names()


def _offscreen(target: Target, size: Size, msaa, anisotropy, backend):
    """The checked arguments of show and record: (the demo's drawable for them, on the context)."""
    from wgpurender.core.course.formats import is_scene_file
    from wgpurender.core.files.assets import resolve_scene
    from wgpurender.core.plan.anisotropy import check_applies
    from wgpurender.wgpu_path.device.context import get_context

    target = _target(target)
    wh, msaa = _size(size) or (640, 480), checks.msaa(msaa)
    anisotropy = checks.choice(anisotropy, "anisotropy", ANISOTROPY_RULES)
    scene = is_scene_file(target)
    check_applies(target, scene, anisotropy)
    name = str(resolve_scene(target)) if scene else target
    return get_context(checks.backend(backend)), name, wh, msaa, anisotropy


@_one_at_a_time
def show(target: Target, size: Size = (640, 480), msaa: int | None = None, anisotropy: str = DEFAULT_ANISOTROPY,
         backend: str | None = None, frames: int | None = None):
    """An interactive view: the stage or scene drawn live, with the demo window's orbit camera (drag to orbit,
    right-drag to pan, scroll to zoom, arrows/WASD, R resets).

    In Jupyter: rendercanvas's Jupyter canvas (jupyter_rfb: ``pip install 'wgpurender[notebook]'``); its display
    carries the first frame as PNG as well, so a frontend without widgets (nbclient, nbconvert, GitHub) shows that
    still. In a script or a terminal: the demo's window (``wgpurender demo``; F1 the overlay, P pause, Esc closes;
    ``frames``: close after that many), then None. Where neither can be (no display, or a kernel without
    jupyter_rfb), one line on stderr says why and the still :class:`Image` is returned."""
    from wgpurender.wgpu_path.notebook import LiveView, Offscreen, in_kernel, widgets_available

    ctx, name, wh, msaa, anisotropy = _offscreen(target, size, msaa, anisotropy, backend)
    if frames is not None and (isinstance(frames, bool) or not isinstance(frames, int) or frames < 1):
        raise UserError(f"frames must be a whole number >= 1 (or None: until the window closes), got {frames!r}")
    if widgets_available():
        return LiveView(ctx, name, wh, msaa, anisotropy)
    if not in_kernel():
        why = _show_window(ctx, name, wh, msaa, anisotropy, frames)
        if not why:
            return None
        print(f"w.show: no window ({why}); returning the still frame (Image.save writes it)", file=sys.stderr)
    pixels = Offscreen(ctx, name, wh, msaa, anisotropy).frame(0.0)
    return Image(pixels, str(target), "wgpu", {}, ctx.describe())


def _show_window(ctx, name: str, size, msaa, anisotropy, frames) -> str:
    """Draw ``name`` in the demo's window until it closes; "" when it did, else why no window could open."""
    from wgpurender.wgpu_path.window import run_window
    from wgpurender.wgpu_path.window.view import DemoView

    view = DemoView(ctx, name, msaa, anisotropy=anisotropy)
    view.check()
    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        return "no display: $DISPLAY and $WAYLAND_DISPLAY are unset"
    try:
        run_window(ctx, view, title=f"wgpurender: {Path(name).name}", size=size, frames=frames)
    except UserError as err:
        return str(err).splitlines()[0]
    return ""


@_one_at_a_time
def record(target: Target, out: str | os.PathLike, seconds: float = 2.0, fps: float = 30.0, size: Size = (640, 480),
           msaa: int | None = None, anisotropy: str = DEFAULT_ANISOTROPY, turn: float | None = None,
           backend: str | None = None, force: bool = False) -> Path:
    """Render ``seconds * fps`` frames into ``out``: an ``.mp4`` (H.264, needs imageio-ffmpeg) or a folder of PNG
    frames (``frames/``). Frame k is at animation time k / fps; ``turn``: degrees the orbit camera turns over the
    clip (default: once round a scene, 0 for a stage, which animates with time). Returns ``out``.
    A video appears whole or not at all; a folder's frames of an earlier recording are replaced, the user's other
    files kept; ``force=True`` records into a non-empty folder that holds no earlier output (docs/security.md)."""
    import math

    from wgpurender.core.files.video import check_output
    from wgpurender.wgpu_path.notebook import Offscreen, record_frames

    if not isinstance(out, (str, os.PathLike)) or not str(out):
        raise UserError(f"out must be a .mp4 file or a folder path, got {type(out).__name__} {out!r}")
    check_output(out)
    force = checks.flag(force, "force")
    for label, value in (("seconds", seconds), ("fps", fps), ("turn", 0.0 if turn is None else turn)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise UserError(f"{label} must be a finite number, got {value!r}")
    if seconds <= 0 or fps <= 0:
        raise UserError(f"seconds and fps must be > 0, got seconds={seconds!r}, fps={fps!r}")
    offscreen = Offscreen(*_offscreen(target, size, msaa, anisotropy, backend))
    degrees = turn if turn is not None else (360.0 if offscreen.view.is_scene else 0.0)
    path, _ = record_frames(offscreen, out, float(seconds), float(fps), float(degrees), force=force)
    return path


__all__ = ["Image", "render", "reference", "compare", "heatmap", "side_by_side", "plan", "explain", "stage_names",
           "reference_stage_names", "export", "show", "record"]
