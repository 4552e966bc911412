"""Frames recorded one ahead (issue 31.4): the next frame's command buffer is recorded and finished right after
this frame's submit, before the wait for this frame's GPU work, so the CPU work runs while the thread is still on
the CPU and the wait sits after it. The Vulkan tutorial's frames in flight do the same with two command buffers
(the raw path's window, FRAMES_IN_FLIGHT = 2); wgpu cannot reuse a command buffer, but a finished one can wait to
be submitted, and ``queue.write_buffer`` stays ordered with the submits around it.

Why: on the H100's virtual machine the same frame's record + submit took 0.134 ms right after a GPU wait but
0.603 ms after the thread slept 20.6 ms (docs/benchmarks.md, "Why CPU per frame grew with the instance count").

What a frame draws does not change: the same calls, the same image at the same clock time (``t`` is the time the
frame is recorded for). The target must stay the same texture between the record and the submit (offscreen; a
swapchain image is acquired later): :meth:`FramesAhead.drop` forgets a frame recorded for an old target or size.
"""

from __future__ import annotations

import wgpu

from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.frame_loop import Record


class FramesAhead:
    """``frame(t)`` submits the frame recorded ahead, then records the next one at ``t`` (one command buffer held)."""

    def __init__(self, ctx: GPUContext, record: Record, target: wgpu.GPUTexture, label: str = "frame-ahead") -> None:
        self.ctx, self.record, self.target, self.label = ctx, record, target, label
        self.pending: wgpu.GPUCommandBuffer | None = None

    def record_next(self, t: float) -> None:
        """Record and finish the next frame at clock time ``t``; it waits for :meth:`submit`."""
        encoder = self.ctx.device.create_command_encoder(label=self.label)
        self.record(encoder, self.target, t)
        self.pending = encoder.finish()

    def submit(self, t: float) -> None:
        """Submit the frame recorded ahead (recorded now, at ``t``, when none is: the first frame, or after
        :meth:`drop`)."""
        if self.pending is None:
            self.record_next(t)
        pending, self.pending = self.pending, None
        self.ctx.queue.submit([pending])

    def frame(self, t: float, t_next: float | None = None) -> None:
        """Submit this frame, then record the next one at ``t_next`` (``t`` when not given) before any wait."""
        self.submit(t)
        self.record_next(t if t_next is None else t_next)

    def drop(self) -> None:
        """Forget the frame recorded ahead (a new target, size or scene state it did not see)."""
        self.pending = None
