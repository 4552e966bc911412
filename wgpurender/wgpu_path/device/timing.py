"""Measuring time: GPU timestamps around passes, and wall-clock statistics of repeated runs.

GPU time comes from timestamp queries written at the start and end of each render
pass (feature "timestamp-query"; wgpu-py 0.32 cannot write them between passes),
resolved into a buffer and read back. Wall time is the median of N runs after a
warm-up, with the 10th and 90th percentiles as the spread: shared machines are
noisy, so compare ratios taken within one run, never absolute numbers across runs.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import wgpu

from wgpurender.wgpu_path.device.context import GPUContext


@dataclass(frozen=True)
class Stats:
    """Median (p50) and spread of a list of samples, in milliseconds; p99 shows a stall a median hides."""

    median: float
    p10: float
    p90: float
    n: int
    p99: float = float("nan")

    @classmethod
    def of(cls, samples_ms: list[float]) -> Stats:
        a = np.asarray(samples_ms, dtype=np.float64)
        p10, p50, p90, p99 = (float(v) for v in np.percentile(a, [10, 50, 90, 99]))
        return cls(p50, p10, p90, len(a), p99)

    def __str__(self) -> str:
        return f"{self.median:.3f} ms [{self.p10:.3f}..{self.p90:.3f}] p99 {self.p99:.3f} (n={self.n})"


def wall_time(fn: Callable[[], object], *, warmup: int = 2, repeats: int = 10) -> Stats:
    """Run ``fn`` ``warmup`` times untimed, then ``repeats`` times timed. ``fn`` must wait for the GPU itself."""
    for _ in range(warmup):
        fn()
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        samples.append((time.perf_counter() - start) * 1e3)
    return Stats.of(samples)


class PassTimer:
    """Timestamp queries for up to ``max_passes`` render or compute passes of one frame.

    Usage per frame: ``timer.reset()``; pass ``timer.writes("scene")`` as the
    pass's ``timestamp_writes``; after the last pass ``timer.resolve(encoder)``;
    after submitting, ``timer.read()`` gives {label: milliseconds}.
    When the adapter lacks "timestamp-query", ``writes`` returns None and
    ``read`` returns an empty dict, so callers need no special case.

    ``frames > 1`` defers the reading, as a benchmark wants: each frame resolves its
    timestamps into its own slot of one buffer, ``read()`` returns {} (the frame loop then
    waits for the GPU its own way), and ``collect()`` maps the buffer once for up to
    ``frames`` frames. Mapping a buffer every frame goes through wgpu-py's poll thread and
    costs a frame more than the raw path's vkGetQueryPoolResults; a benchmark that timed
    it would be timing the stopwatch.
    """

    SLOT_ALIGNMENT = 256  # resolve_query_set's destination offset must be a multiple of 256

    def __init__(self, ctx: GPUContext, max_passes: int = 16, frames: int = 1) -> None:
        self.ctx = ctx
        self.enabled = ctx.has("timestamp-query")
        self.labels: list[str] = []
        self.max_passes = max_passes
        self.frames = max(1, frames)
        self._slots: list[list[str]] = []  # deferred mode: the labels of each resolved frame
        if not self.enabled:
            return
        from wgpurender.wgpu_path.device.native import timestamp_period_ns

        self.period_ns = timestamp_period_ns(ctx)
        count = 2 * max_passes
        align = self.SLOT_ALIGNMENT
        self.slot_size = (8 * count + align - 1) // align * align
        self.query_set = ctx.device.create_query_set(type="timestamp", count=count)
        self.resolve_buffer = ctx.device.create_buffer(
            size=self.slot_size * self.frames, usage=wgpu.BufferUsage.QUERY_RESOLVE | wgpu.BufferUsage.COPY_SRC
        )
        self.read_buffer = ctx.device.create_buffer(
            size=self.slot_size * self.frames, usage=wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.MAP_READ
        )

    @property
    def deferred(self) -> bool:
        return self.frames > 1

    def reset(self) -> None:
        self.labels = []

    def writes(self, label: str) -> dict | None:
        if not self.enabled or len(self.labels) >= self.max_passes:
            return None
        i = len(self.labels)
        self.labels.append(label)
        return {
            "query_set": self.query_set,
            "beginning_of_pass_write_index": 2 * i,
            "end_of_pass_write_index": 2 * i + 1,
        }

    def resolve(self, encoder: wgpu.GPUCommandEncoder) -> None:
        if not self.enabled or not self.labels:
            return
        n = 2 * len(self.labels)
        if not self.deferred:
            encoder.resolve_query_set(self.query_set, 0, n, self.resolve_buffer, 0)
            encoder.copy_buffer_to_buffer(self.resolve_buffer, 0, self.read_buffer, 0, 8 * n)
            return
        if len(self._slots) >= self.frames:
            raise RuntimeError(f"PassTimer: {self.frames} frames resolved without collect()")
        encoder.resolve_query_set(self.query_set, 0, n, self.resolve_buffer, len(self._slots) * self.slot_size)
        self._slots.append(list(self.labels))

    def _ms(self, ticks: np.ndarray, labels: list[str]) -> dict[str, float]:
        out: dict[str, float] = {}
        for i, label in enumerate(labels):
            out[label] = out.get(label, 0.0) + (ticks[2 * i + 1] - ticks[2 * i]) * self.period_ns / 1e6
        return out

    def read(self) -> dict[str, float]:
        """Milliseconds per labelled pass; blocks until the frame is done. {} when deferred (see collect)."""
        if not self.enabled or not self.labels or self.deferred:
            return {}
        n = 2 * len(self.labels)
        self.ctx.map_read(self.read_buffer, 0, 8 * n)
        ticks = np.frombuffer(self.read_buffer.read_mapped(0, 8 * n), dtype=np.uint64).astype(np.float64)
        self.read_buffer.unmap()
        return self._ms(ticks, self.labels)

    def collect(self) -> list[dict[str, float]]:
        """Deferred mode: {label: ms} of every frame resolved since the last collect, oldest first."""
        if not self.enabled or not self._slots:
            self._slots = []
            return []
        size = len(self._slots) * self.slot_size
        encoder = self.ctx.device.create_command_encoder(label="timestamps")
        encoder.copy_buffer_to_buffer(self.resolve_buffer, 0, self.read_buffer, 0, size)
        self.ctx.queue.submit([encoder.finish()])
        self.ctx.map_read(self.read_buffer, 0, size)
        data = np.frombuffer(self.read_buffer.read_mapped(0, size), dtype=np.uint64).astype(np.float64)
        self.read_buffer.unmap()
        per_slot = self.slot_size // 8
        out = [self._ms(data[k * per_slot:(k + 1) * per_slot], labels) for k, labels in enumerate(self._slots)]
        self._slots = []
        return out
