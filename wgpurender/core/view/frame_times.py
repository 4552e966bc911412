"""Both demo windows' frame counters: FPS in the title, and the benchmark mode.

The benchmark mode follows Sascha Willems' Vulkan examples: warm up, run for a while, write frame times.

``wgpurender demo TARGET --benchmark`` draws untimed for ``warmup`` seconds (shader JIT,
first uploads, the swapchain settling), then records the wall time of every frame for
``runtime`` seconds and writes one CSV row per frame: ``frame,frame_ms``. A frame's time is
from the start of one loop iteration to the start of the next (poll input, record, submit,
present), the time a user waits for it; with the fifo present mode it includes waiting for
vblank. API-free: both windows (wgpurender/wgpu_path/window/ and ``demo --raw``'s
wgpurender/raw_path/window/__init__.py) feed the same recorder, so their CSVs are written the same way.
"""

from __future__ import annotations

import csv
import statistics
from dataclasses import dataclass, field
from pathlib import Path


@dataclass
class BenchmarkSpec:
    warmup_s: float = 2.0
    runtime_s: float = 10.0
    csv_path: Path = Path("benchmark.csv")


@dataclass
class FrameRecorder:
    """Feeds on frame boundaries; knows when the warm-up ended and the run is over."""

    spec: BenchmarkSpec
    frame_ms: list[float] = field(default_factory=list)
    _start: float | None = None
    _last: float | None = None

    def frame_done(self, now: float) -> None:
        """Call once per presented frame with time.perf_counter()."""
        if self._start is None:
            self._start = now
        elif now - self._start >= self.spec.warmup_s:
            if self._last is not None and self._last - self._start >= self.spec.warmup_s:
                self.frame_ms.append((now - self._last) * 1e3)
        self._last = now

    def finished(self) -> bool:
        return sum(self.frame_ms) >= self.spec.runtime_s * 1e3

    def write_csv(self) -> Path:
        """frame,frame_ms rows, written to a temporary file first so a failed run clobbers nothing."""
        path = Path(self.spec.csv_path)
        tmp = path.with_name(path.name + ".part")
        with tmp.open("w", newline="", encoding="utf-8") as fh:
            writer = csv.writer(fh)
            writer.writerow(["frame", "frame_ms"])
            writer.writerows((k, f"{ms:.4f}") for k, ms in enumerate(self.frame_ms))
        tmp.replace(path)
        return path

    def summary(self) -> str:
        times = self.frame_ms
        if not times:
            return "benchmark: no frames recorded (runtime too short?)"
        mean = statistics.fmean(times)
        q = statistics.quantiles(times, n=100) if len(times) > 1 else [times[0]] * 99
        return (f"benchmark: {len(times)} frames in {sum(times) / 1e3:.2f} s, {1e3 / mean:.1f} FPS; frame time "
                f"mean {mean:.3f} ms, min {min(times):.3f}, p50 {q[49]:.3f}, p99 {q[98]:.3f}, max {max(times):.3f} ms")


TITLE_EVERY_S = 0.5  # how often the FPS in the title is refreshed


@dataclass
class TitleCounter:
    """FPS and mean frame time over the last ``TITLE_EVERY_S``, for the window title (both windows)."""

    base: str
    _at: float | None = None
    _frames: int = 0

    def frame_done(self, now: float, status: str = "") -> str | None:
        """Count a presented frame; every TITLE_EVERY_S the new title, otherwise None."""
        if self._at is None:
            self._at = now
            return None
        self._frames += 1
        if now - self._at < TITLE_EVERY_S:
            return None
        ms = (now - self._at) * 1e3 / self._frames
        self._at, self._frames = now, 0
        return title_text(self.base, ms, status)


def title_text(base: str, frame_ms: float, status: str = "") -> str:
    """``base  |  60.0 FPS  16.67 ms`` (plus a status such as a failed reload)."""
    return f"{base}  |  {1e3 / frame_ms:.1f} FPS  {frame_ms:.2f} ms{status}"
