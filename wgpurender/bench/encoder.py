"""A command encoder that puts GPU timestamps on every render pass someone else begins.

Stages and post effects begin their own passes; wrapping the encoder they are given
adds ``timestamp_writes`` (labelled by the pass's label, else the wrapper's) without
changing their code. Everything else is forwarded to the real encoder.
"""

from __future__ import annotations

import time

import wgpu

from ..gpu import GPUContext
from ..timing import PassTimer


class TimedEncoder:
    def __init__(self, encoder: wgpu.GPUCommandEncoder, timer: PassTimer, label: str) -> None:
        self._encoder = encoder
        self._timer = timer
        self._label = label

    def __getattr__(self, name: str):
        return getattr(self._encoder, name)

    def begin_render_pass(self, **kwargs):
        if kwargs.get("timestamp_writes") is None:
            kwargs["timestamp_writes"] = self._timer.writes(self._label)
        return self._encoder.begin_render_pass(**kwargs)


def finish_frame(
    ctx: GPUContext,
    encoder: wgpu.GPUCommandEncoder,
    timer: PassTimer,
    start: float,
    readback_target: wgpu.GPUTexture | None = None,
) -> tuple[float, dict[str, float]]:
    """End a timed frame the same way for every runner: resolve, submit, read back, wait.

    Returns the CPU milliseconds from ``start`` (a perf_counter value) to the submit
    and the GPU milliseconds per pass label (empty without timestamp queries).
    """
    timer.resolve(encoder)
    ctx.queue.submit([encoder.finish()])
    cpu_ms = (time.perf_counter() - start) * 1e3
    if readback_target is not None:
        from ..targets import read_texture

        read_texture(ctx, readback_target)
    gpu = timer.read()  # maps the query buffer: waits for the frame
    if not gpu:
        ctx.wait_idle()
    return cpu_ms, gpu


def gpu_total(gpu: dict[str, float]) -> float | None:
    return sum(gpu.values()) if gpu else None
