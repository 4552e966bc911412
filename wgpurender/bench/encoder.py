"""A command encoder that puts GPU timestamps on every render pass someone else begins.

Stages and post effects begin their own passes; wrapping the encoder they are given
adds ``timestamp_writes`` (labelled by the pass's label, else the wrapper's) without
changing their code. Everything else is forwarded to the real encoder.
"""

from __future__ import annotations

import wgpu

from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.frame_loop import Record, run_frame
from wgpurender.wgpu_path.device.timing import PassTimer


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


def timed_frame(ctx: GPUContext, record: Record, target: wgpu.GPUTexture, timer: PassTimer, label: str,
                t: float = 0.0, read_back: bool = False) -> tuple[float, dict[str, float]]:
    """One frame through the frame loop with every render pass ``record`` begins timestamped.

    Returns the CPU milliseconds of record + submit and the GPU milliseconds per pass label
    (empty without timestamp queries).
    """
    def timed(encoder: wgpu.GPUCommandEncoder, tgt: wgpu.GPUTexture, t: float) -> None:
        record(TimedEncoder(encoder, timer, label), tgt, t)

    frame = run_frame(ctx, timed, target, t, label=label, read_back=read_back, timer=timer)
    return frame.cpu_ms, frame.gpu_ms


def gpu_total(gpu: dict[str, float]) -> float | None:
    return sum(gpu.values()) if gpu else None
