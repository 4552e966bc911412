"""One frame on the wgpu path: record, submit, read back, time. Every headless frame goes through here.

The headless runner (render.py), the scene renderer's headless path and the benchmarks call
:func:`run_frame`; the window is meant to as well. The API (stable, others build on it):

- ``record(encoder, target, t)``: any callable that records one frame's commands into an encoder,
  drawing into ``target`` at time ``t`` (a stage's or a SceneRenderer's bound ``record`` method);
- :func:`run_frame` ``(ctx, record, target, t=0.0, *, label="frame", read_back=True, timer=None,
  wait=False) -> Frame``: creates an encoder, calls ``record``, resolves the timer's queries (if any),
  records the copy of ``target`` to the host into the same encoder (``read_back``, as the raw path
  records vkCmdCopyImageToBuffer into the frame's command buffer), submits once, then reads the copy
  (one host buffer per context, reused), reads the timer (which waits for the GPU), or waits for the
  GPU (``wait``, or a timer without timestamps) - in that order;
- :func:`run_frames` ``(ctx, record, target, frames, t=0.0, ...) -> Frame``: ``frames`` frames, the
  last one returned (the first pays for lazy driver work such as shader JIT);
- :class:`Frame`: ``pixels`` (or None), ``frame_ms`` (wall time from the encoder to the end of the
  frame: readback or wait included), ``cpu_ms`` (record + submit), ``gpu_ms`` (per pass label, empty
  without a timer or timestamp queries).

A window calls ``run_frame(ctx, record, swapchain_texture, t, read_back=False)`` and presents.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import wgpu

from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.targets import Readback
from wgpurender.wgpu_path.device.timing import PassTimer

if TYPE_CHECKING:  # pragma: no cover
    from wgpurender.core.plan import RenderPlan

Record = Callable[[wgpu.GPUCommandEncoder, wgpu.GPUTexture, float], None]


@dataclass
class Frame:
    pixels: np.ndarray | None
    frame_ms: float
    cpu_ms: float
    gpu_ms: dict[str, float] = field(default_factory=dict)


@dataclass
class RenderResult:
    """What a headless render returns: the last frame's pixels and time, and the adapter that made it."""

    pixels: np.ndarray
    frame_ms: float  # wall time of one steady-state frame: encode, submit, GPU, readback
    adapter: str
    plan: RenderPlan | None = None  # the plan a scene was drawn from (None for a stage)


def run_frame(ctx: GPUContext, record: Record, target: wgpu.GPUTexture, t: float = 0.0, *, label: str = "frame",
              read_back: bool = True, timer: PassTimer | None = None, wait: bool = False) -> Frame:
    """Record, submit, read back and time one frame (see the module docstring)."""
    start = time.perf_counter()
    if timer is not None:
        timer.reset()
    encoder = ctx.device.create_command_encoder(label=label)
    record(encoder, target, t)
    if timer is not None:
        timer.resolve(encoder)
    readback = _readback(ctx) if read_back else None
    if readback is not None:
        readback.record(encoder, target)
    ctx.queue.submit([encoder.finish()])
    cpu_ms = (time.perf_counter() - start) * 1e3
    pixels = readback.read() if readback is not None else None
    gpu = timer.read() if timer is not None else {}  # maps the query buffer: waits for the frame
    if wait or (timer is not None and not gpu):
        ctx.wait_idle()
    return Frame(pixels, (time.perf_counter() - start) * 1e3, cpu_ms, gpu)


def _readback(ctx: GPUContext) -> Readback:
    """The context's frame readback (one reused host buffer)."""
    if ctx.frame_readback is None:
        ctx.frame_readback = Readback(ctx)
    return ctx.frame_readback


def run_frames(ctx: GPUContext, record: Record, target: wgpu.GPUTexture, frames: int, t: float = 0.0,
               **kwargs) -> Frame:
    """``frames`` frames (at least one) through :func:`run_frame`; the last one."""
    frame = None
    for _ in range(max(1, frames)):
        frame = run_frame(ctx, record, target, t, **kwargs)
    return frame
