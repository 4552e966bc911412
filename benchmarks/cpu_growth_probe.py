"""Why does CPU per frame (record + submit) grow with the instance count on the H100 (issue 31.3: 0.19 ms at 1k,
0.69 ms at 1M) when the recorded frame is the same at every count? A probe, run on the device.

For each count of `bench perf`'s scene-scale family (the same scene files, wgpurender/bench/scale.py), it first
counts the frame's native calls (bench/calls.py): if they are equal at every count, the frame does no more work
at 1M than at 1k. Then it times record + submit in wall time and in thread CPU time (`time.thread_time`)
under three waits for the GPU between frames:

- `block`: `ctx.wait_idle()`, the frame loop's wait (wgpuDevicePoll(wait=True): the thread sleeps in the
  driver until the GPU is done);
- `spin`: a busy loop for 1.05x the `block` frame time after the submit, then the blocking wait (which then
  returns at once): the thread stays awake
  (wgpuDevicePoll(wait=False) cannot be spun on: in wgpu-native 29 it returns "queue empty" while work is
  still pending, measured on lavapipe);
- `block+sleep`: the blocking wait and then `time.sleep` for the largest count's frame time, so the thread
  is idle for as long as at the largest count but records the smallest count's frame.

If `block` grows with the count, `spin` is flat, and `block+sleep` at the smallest count costs what `block` costs
at the largest, the growth comes from the thread waking up after the GPU wait, not from the instance count.

Two more waits ask what keeping the core awake would cost a product (issue 31.4's frametime pass):

- `sleep+spin T`: sleep until T ms before the frame's expected end (the `block` frame's median), then spin until
  that end, then the blocking wait: a bounded spin of about T ms a frame instead of the whole frame;
- every row also reports `wait_thread_cpu_ms`: the CPU time the thread spent in the wait (what the wait burns).

And `spin+calls`: the `spin` wait again, with every wgpu-native call timed (wgpu-py's `libf`; the wrapping adds a
little to each call), so a count whose spinning row still costs more (100k: GPU-culled, indirect) shows which
native call grows: `native_us` lists the largest medians.

    python benchmarks/cpu_growth_probe.py OUT.csv [COUNTS] [FRAMES]
"""

from __future__ import annotations

import csv
import statistics
import sys
import tempfile
import time
from pathlib import Path

from wgpurender.bench import scale
from wgpurender.bench.calls import steady_calls
from wgpurender.bench.frames import settle_garbage
from wgpurender.bench.scene import SceneRunner
from wgpurender.wgpu_path.device.context import get_context

SIZE = (800, 600)
TAILS_MS = (0.25, 1.0)  # the spin before the expected end of the frame, for the sleep+spin waits


def spin_wait(seconds: float):
    """A wait that keeps the thread busy for ``seconds`` after the submit, then blocks for the rest."""
    def wait(ctx, submitted: float) -> None:
        while time.perf_counter() - submitted < seconds:
            pass
        ctx.wait_idle()

    return wait


def block(ctx, submitted: float) -> None:
    ctx.wait_idle()


def sleep_spin_wait(expected_s: float, tail_s: float):
    """Sleep until ``tail_s`` before the expected end of the frame (``expected_s`` after the submit), spin to that
    end, then block for whatever is left."""
    def wait(ctx, submitted: float) -> None:
        end = submitted + expected_s
        rest = end - tail_s - time.perf_counter()
        if rest > 0:
            time.sleep(rest)
        while time.perf_counter() < end:
            pass
        ctx.wait_idle()

    return wait


class NativeTimes:
    """Every wgpu-native call through wgpu-py's ``libf`` timed while active (microseconds per call, per frame)."""

    def __init__(self) -> None:
        from wgpu.backends.wgpu_native import _api

        self.libf, self.frame, self.frames = _api.libf, {}, []
        self.real = {n: getattr(self.libf, n) for n in dir(self.libf) if n.startswith("wgpu")}
        for name, real in self.real.items():
            setattr(self.libf, name, self._timed(name, real))

    def _timed(self, name, real):
        def call(*args):
            start = time.perf_counter()
            try:
                return real(*args)
            finally:
                self.frame[name] = self.frame.get(name, 0.0) + (time.perf_counter() - start) * 1e6
        return call

    def next_frame(self) -> None:
        self.frames.append(self.frame)
        self.frame = {}

    def summary(self, skip: int = 5) -> str:
        frames = self.frames[skip:]
        names = {n for f in frames for n in f if n != "wgpuDevicePoll"}
        medians = {n: statistics.median(f.get(n, 0.0) for f in frames) for n in names}
        largest = sorted(medians.items(), key=lambda item: -item[1])[:6]
        return "; ".join(f"{n.removeprefix('wgpu')} {v:.1f}" for n, v in largest)

    def close(self) -> None:
        for name, real in self.real.items():
            setattr(self.libf, name, real)


def timed(ctx, runner, frames: int, wait, idle_s: float = 0.0, native: NativeTimes | None = None) -> tuple:
    """(wall ms, thread CPU ms, frame ms, thread CPU ms in the wait) of record + submit, per frame, after ``wait``
    (and ``idle_s``)."""
    wall, cpu, frame, burnt = [], [], [], []
    record, target, dev, queue = runner.renderer.record, runner.target, ctx.device, ctx.queue
    for _ in range(frames + 5):
        w0, c0 = time.perf_counter(), time.thread_time()
        encoder = dev.create_command_encoder(label="probe")
        record(encoder, target, 0.0)
        queue.submit([encoder.finish()])
        w1, c1 = time.perf_counter(), time.thread_time()
        if native is not None:
            native.next_frame()
        wait(ctx, w1)
        frame.append((time.perf_counter() - w0) * 1e3)
        burnt.append((time.thread_time() - c1) * 1e3)
        if idle_s:
            time.sleep(idle_s)
        wall.append((w1 - w0) * 1e3)
        cpu.append((c1 - c0) * 1e3)
    return wall[5:], cpu[5:], frame[5:], burnt[5:]


def row(n: int, wait: str, measured: tuple, calls: int, native: str = "") -> tuple:
    wall, cpu, frame, burnt = (statistics.median(m) for m in measured)
    return n, wait, wall, cpu, frame, burnt, calls, native


def main() -> int:
    out = Path(sys.argv[1])
    counts = [int(c) for c in (sys.argv[2] if len(sys.argv) > 2 else "1000,10000,100000,1000000").split(",")]
    frames = int(sys.argv[3]) if len(sys.argv) > 3 else 40
    ctx = get_context()
    rows, idle = [], 0.0
    with tempfile.TemporaryDirectory() as tmp:
        runners = {n: SceneRunner(ctx, scale.instanced_scene(Path(tmp), n, SIZE), SIZE) for n in counts}
        for runner in runners.values():
            runner.frame(readback=True)
        settle_garbage()
        for n, runner in runners.items():
            calls = sum(steady_calls(ctx, runner.renderer.record, runner.target).values())
            measured = timed(ctx, runner, frames, block)
            rows.append(row(n, "block", measured, calls))
            expected = statistics.median(measured[2]) / 1e3
            busy = 1.05 * expected
            rows.append(row(n, "spin", timed(ctx, runner, frames, spin_wait(busy)), calls))
            for tail in TAILS_MS:
                rows.append(row(n, f"sleep+spin {tail} ms", timed(ctx, runner, frames,
                                                                  sleep_spin_wait(expected, tail / 1e3)), calls))
            native = NativeTimes()
            try:
                measured = timed(ctx, runner, frames, spin_wait(busy), native=native)
            finally:
                native.close()
            rows.append(row(n, "spin+calls", measured, calls, native.summary()))
            idle = expected
        n = min(counts)
        rows.append(row(n, f"block+sleep {idle * 1e3:.1f} ms", timed(ctx, runners[n], frames, block, idle), rows[0][6]))
    with out.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(("instances", "wait", "record_submit_wall_ms", "record_submit_thread_cpu_ms", "frame_ms",
                    "wait_thread_cpu_ms", "native_calls", "native_us"))
        w.writerows((n, m, f"{a:.4f}", f"{b:.4f}", f"{c:.4f}", f"{d:.4f}", k, x) for n, m, a, b, c, d, k, x in rows)
    print(out.read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
