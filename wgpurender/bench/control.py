"""``bench perf``'s control family: the host's own tail, sampled exactly as the frame rows are (issue 31.4).

The p99 goal ("p99 at most 2x the median in bench perf's frame rows") was over in rows of every path, raw Vulkan
included, and the notes put the tails on the virtual machine's host; no row showed the host's own jitter. These
rows do, with no renderer in them. Each is a runner of the frame protocol (``frame(readback) -> (cpu_ms, None)``)
timed by :func:`wgpurender.bench.frames.measure`: the same sample count as the frame rows (``PerfConfig.timed_frames``
gives this family the tail count), the same warm-up until stable, the same collector handling (frozen before,
paused during) and the same clock (``time.perf_counter``). Rows ``frame_ms`` (the call, wall) and ``cpu_ms`` (the
runner's own part):

- ``cpu-fixed``: a fixed pure-CPU workload of about one frame's CPU length (:data:`TARGET_MS`): one ``zlib.crc32``
  over a buffer made once, sized once per run so one pass takes about the target; no GPU, no Python loop, nothing
  allocated but the checksum's int. Its tail is the host's: descheduling, interrupts, frequency changes.
- ``gpu-empty``: an empty GPU round trip: a command encoder, its finish, one submit (``cpu_ms``) and the wait for
  the GPU (``frame_ms``), the frame rows' own calls with nothing recorded: the driver's and wgpu-native's tail.
"""

from __future__ import annotations

import dataclasses
import statistics
import time
import zlib

from wgpurender.bench.frames import measure
from wgpurender.bench.markdown_scale import CONTROL as FAMILY
from wgpurender.bench.report import Result

TARGET_MS = 0.3  # about the final scene's CPU per frame on the H100 (issue 31.4's 0.3 ms)
PROBE_BYTES = 64 * 1024  # the calibration pass: in a core's L2
MAX_BYTES = 16 * 1024 * 1024  # a bound on the buffer, whatever a calibration pass reads
SIZE = ""  # the control has no image size


def calibrated_bytes(target_ms: float = TARGET_MS, probes: int = 15) -> int:
    """How many bytes one crc32 pass walks in about ``target_ms`` here: the median of ``probes`` timed passes over
    :data:`PROBE_BYTES`, scaled (a multiple of 1 KiB, at least one probe's and at most :data:`MAX_BYTES`)."""
    buffer = bytes(PROBE_BYTES)
    times = []
    for _ in range(probes):
        start = time.perf_counter()
        zlib.crc32(buffer)
        times.append(time.perf_counter() - start)
    per_byte = max(statistics.median(times), 1e-9) / PROBE_BYTES
    want = int(target_ms / 1e3 / per_byte) // 1024 * 1024
    return min(MAX_BYTES, max(PROBE_BYTES, want))


class CpuWorkload:
    """One crc32 pass over a fixed buffer per frame: pure CPU, the same work every frame."""

    def __init__(self, size_bytes: int | None = None) -> None:
        self.size_bytes = size_bytes or calibrated_bytes()
        self.buffer = bytes(range(256)) * (self.size_bytes // 256)
        self.checksum = 0

    def run(self) -> int:
        """The workload itself (what a frame times)."""
        return zlib.crc32(self.buffer)

    def frame(self, readback: bool = False) -> tuple[float, None]:
        start = time.perf_counter()
        self.checksum = self.run()
        return (time.perf_counter() - start) * 1e3, None


class EmptyGpuRoundTrip:
    """An encoder with nothing recorded, its finish and one submit (``cpu_ms``), then the wait for the GPU."""

    def __init__(self, ctx) -> None:
        self.ctx = ctx

    def frame(self, readback: bool = False) -> tuple[float, None]:
        start = time.perf_counter()
        encoder = self.ctx.device.create_command_encoder(label="bench-control")
        self.ctx.queue.submit([encoder.finish()])
        cpu_ms = (time.perf_counter() - start) * 1e3
        self.ctx.wait_idle()
        return cpu_ms, None


def bench_control(ctx, frames: int) -> list[Result]:
    """Both control rows (frame_ms, cpu_ms each), ``frames`` samples a row, as :func:`frames.measure` takes them."""
    cpu = CpuWorkload()
    out = measure(cpu, frames).results(FAMILY, "cpu-fixed", "host", (0, 0),
                                       note=f"one zlib.crc32 over {cpu.size_bytes} bytes (about {TARGET_MS} ms here)")
    out += measure(EmptyGpuRoundTrip(ctx), frames).results(
        FAMILY, "gpu-empty", "wgpu", (0, 0), note="empty encoder + finish + submit (cpu_ms), then the GPU wait")
    return [dataclasses.replace(r, size=SIZE) for r in out]
