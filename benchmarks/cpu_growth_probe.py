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


def spin_wait(seconds: float):
    """A wait that keeps the thread busy for ``seconds`` after the submit, then blocks for the rest."""
    def wait(ctx, submitted: float) -> None:
        while time.perf_counter() - submitted < seconds:
            pass
        ctx.wait_idle()

    return wait


def block(ctx, submitted: float) -> None:
    ctx.wait_idle()


def timed(ctx, runner, frames: int, wait, idle_s: float = 0.0) -> tuple[list[float], list[float], list[float]]:
    """(wall ms, thread CPU ms, frame ms) of record + submit, per frame, after ``wait`` (and ``idle_s``)."""
    wall, cpu, frame = [], [], []
    record, target, dev, queue = runner.renderer.record, runner.target, ctx.device, ctx.queue
    for _ in range(frames + 5):
        w0, c0 = time.perf_counter(), time.thread_time()
        encoder = dev.create_command_encoder(label="probe")
        record(encoder, target, 0.0)
        queue.submit([encoder.finish()])
        w1, c1 = time.perf_counter(), time.thread_time()
        wait(ctx, w1)
        frame.append((time.perf_counter() - w0) * 1e3)
        if idle_s:
            time.sleep(idle_s)
        wall.append((w1 - w0) * 1e3)
        cpu.append((c1 - c0) * 1e3)
    return wall[5:], cpu[5:], frame[5:]


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
            calls = steady_calls(ctx, runner.renderer.record, runner.target)
            wall, cpu, frame = timed(ctx, runner, frames, block)
            rows.append((n, "block", statistics.median(wall), statistics.median(cpu), statistics.median(frame),
                         sum(calls.values())))
            busy = 1.05 * statistics.median(frame) / 1e3
            wall, cpu, frame = timed(ctx, runner, frames, spin_wait(busy))
            rows.append((n, "spin", statistics.median(wall), statistics.median(cpu), statistics.median(frame),
                         sum(calls.values())))
            idle = busy / 1.05
        n = min(counts)
        wall, cpu, frame = timed(ctx, runners[n], frames, block, idle)
        rows.append((n, f"block+sleep {idle * 1e3:.1f} ms", statistics.median(wall), statistics.median(cpu),
                     statistics.median(frame), rows[0][5]))
    with out.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(("instances", "wait", "record_submit_wall_ms", "record_submit_thread_cpu_ms", "frame_ms",
                    "native_calls"))
        w.writerows((n, m, f"{a:.4f}", f"{b:.4f}", f"{c:.4f}", k) for n, m, a, b, c, k in rows)
    print(out.read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
