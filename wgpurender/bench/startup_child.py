"""The startup family's child process: one path's first pixel, timed from the child's first statement.

The parent (bench/startup.py) starts ``python -c`` with :data:`LAUNCH`, whose first statement reads the clock
before anything is imported (this package included), so both paths are timed from the same point and every
import, shared or not, is inside ``total_ms``. The child prints one JSON line: its phases, and ``done_at``, the
clock at the first pixels (``time.perf_counter`` is the system-wide monotonic clock, so the parent subtracts its
own reading from before the spawn: ``spawn_ms``, interpreter start-up included).

The wgpu child does what ``wgpurender render`` does (the API's ``render``): it loads the Vulkan drivers'
libraries on a thread (``driver_preload.start``) before importing wgpu-py, and starts making the device on a
thread (``context.start_context``) before importing the renderer and the stages, so its ``import_ms`` runs beside
the driver's work and its ``context_ms`` is what is left of making the device after the imports; ``make_ms`` is
how long making it took on that thread. The raw child makes its device after its imports, as the raw path does.
Neither writes an image file: the first pixels are the frame's bytes in host memory.
"""

from __future__ import annotations

import time

PHASES = ("import_ms", "context_ms", "setup_ms", "first_frame_ms", "second_frame_ms", "total_ms")
NO_PRELOAD_ARG = "no-preload"  # a 4th argument: the wgpu child leaves the drivers to the Vulkan loader
# The command line's code: the clock first, then the child. ``sys.argv[1:]`` = path, stage, WxH[, no-preload].
LAUNCH = ("import time; t0 = time.perf_counter(); import sys; from wgpurender.bench.startup_child import main; "
          "main(t0, sys.argv[1:])")


def child(path: str, stage: str, size: tuple[int, int], t0: float, preload: bool = True) -> dict[str, float]:
    """Draw ``stage`` twice on ``path``; the phases in ms since ``t0`` (each phase from the mark before it)."""
    marks = _wgpu(stage, size, preload) if path == "wgpu" else _raw(stage, size)
    out, last = {}, t0
    for name in PHASES[:-1]:
        out[name] = (marks[name] - last) * 1e3
        last = marks[name]
    out["total_ms"] = (marks["first_frame_ms"] - t0) * 1e3  # to the first pixels
    out["done_at"] = marks["first_frame_ms"]
    if "make_ms" in marks:
        out["make_ms"] = marks["make_ms"]
    return out


def _wgpu(stage: str, size: tuple[int, int], preload: bool) -> dict[str, float]:
    if preload:
        from wgpurender.wgpu_path.device import driver_preload

        driver_preload.start()  # as `wgpurender render` does: the drivers load on a thread while wgpu-py is imported
    from wgpurender.wgpu_path.device import context

    made = _time_make(context)
    context.start_context()  # as `wgpurender render` does: the device is made while the rest is imported
    from wgpurender.wgpu_path.device.frame_loop import run_frame
    from wgpurender.wgpu_path.device.targets import create_target
    from wgpurender.wgpu_path.stages import get_stage

    marks = {}
    cls = get_stage(stage)  # imports the stage modules
    marks["import_ms"] = time.perf_counter()
    ctx = context.get_context()  # what is left of making it
    marks["context_ms"] = time.perf_counter()
    st = cls(ctx, cls.default_format, None)
    st.resize(size)
    target = create_target(ctx, size, st.format)
    marks["setup_ms"] = time.perf_counter()
    for name in ("first_frame_ms", "second_frame_ms"):
        run_frame(ctx, st.record, target, 0.0)
        marks[name] = time.perf_counter()
    marks["make_ms"] = made.get("ms", float("nan"))
    return marks


def _time_make(context) -> dict[str, float]:
    """Time the device's making (on whichever thread) by wrapping the context module's maker: the bench's
    instrument, nothing else changes."""
    made: dict[str, float] = {}
    real = context._make_context

    def timed(backend: str):
        start = time.perf_counter()
        try:
            return real(backend)
        finally:
            made["ms"] = (time.perf_counter() - start) * 1e3

    context._make_context = timed
    return made


def _raw(stage: str, size: tuple[int, int]) -> dict[str, float]:
    from wgpurender.bench.raw_frames import RawStageRunner  # no wgpu-py: the raw path's own imports only
    from wgpurender.raw_path.device.context import get_vulkan

    marks = {"import_ms": time.perf_counter()}
    get_vulkan()
    marks["context_ms"] = time.perf_counter()
    runner = RawStageRunner(stage, size)
    marks["setup_ms"] = time.perf_counter()
    for name in ("first_frame_ms", "second_frame_ms"):
        runner.frame(readback=True)
        marks[name] = time.perf_counter()
    runner.close()
    return marks


def main(t0: float, argv: list[str]) -> None:
    import json

    path, stage, size, *variant = argv
    w, h = (int(v) for v in size.split("x"))
    print(json.dumps(child(path, stage, (w, h), t0, preload=NO_PRELOAD_ARG not in variant)))
