"""What each slow frame of bench perf's frame rows was doing (issue 31.4: p99 <= 2x the median), on the wgpu path.

benchmarks/tail_probe.py showed where the slow frames sit (in blocks, not after the bench's own work). This probe
asks what they are: each timed frame of a few cases is drawn the way ``bench perf`` draws it (bench/frames.py: warm
until stable, the collector frozen and paused, the runner's own frame), and around its record + submit alone (the
``cpu_ms`` sample: from the start of ``record`` to the return of ``queue.submit``) it reads this thread's counters:

- ``thread_cpu_ms``: CPU time this thread ran (``time.thread_time``); a sample whose wall time is far above it was
  off the CPU (preempted, or waiting for the GIL);
- ``nivcsw``: involuntary context switches (``getrusage(RUSAGE_THREAD)``): the kernel took the CPU away;
- ``nvcsw``: voluntary ones: the thread blocked (a lock, the GIL handed to another thread, a driver wait);
- ``minflt``: page faults (memory touched for the first time, e.g. a new buffer);
- ``gc``: collections the garbage collector ran (``gc.get_stats``; the bench pauses it, so this should be 0);
- ``threads``: the Python threads alive (wgpu-py's poll thread, an early-context thread).

Each slow sample (cpu_ms over 2x the case's median) is put in the first class that fits: ``gc``, ``faults``,
``preempted`` (nivcsw > 0), ``blocked`` (nvcsw > 0), ``off-cpu`` (wall > 1.5x its thread CPU time), and else
``slow on cpu`` (it ran the whole time, just slower: a cold core, a lower clock, a noisy neighbour's caches).

    python benchmarks/tail_cause_probe.py OUT.csv [FRAMES]
"""

from __future__ import annotations

import gc
import resource
import statistics
import sys
import threading
import time
from pathlib import Path

from probe_csv import write_rows

STAGES = (("clear", (800, 600)), ("clear-pass", (800, 600)), ("triangle", (1280, 720)), ("textured", (800, 600)),
          ("msaa-post", (1920, 1080)))
SCENES = (("final.toml", (800, 600)), ("final.toml", (3840, 2160)))
COUNTERS = ("ru_nivcsw", "ru_nvcsw", "ru_minflt")


def _snapshot() -> tuple:
    ru = resource.getrusage(resource.RUSAGE_THREAD)
    return (time.thread_time(), *(getattr(ru, c) for c in COUNTERS), sum(s["collections"] for s in gc.get_stats()))


class Watched:
    """Wraps a runner's record and the queue's submit: the counters between the start of one and the end of other."""

    def __init__(self, ctx, owner, attribute: str) -> None:
        self.start = self.end = None
        record = getattr(owner, attribute)

        def watched_record(*args, **kwargs):
            self.start = _snapshot()
            return record(*args, **kwargs)

        submit = ctx.queue.submit

        def watched_submit(*args, **kwargs):
            result = submit(*args, **kwargs)
            self.end = _snapshot()
            return result

        setattr(owner, attribute, watched_record)
        ctx.queue.submit = watched_submit
        self._undo = lambda: (delattr(owner, attribute), delattr(ctx.queue, "submit"))

    def delta(self) -> dict:
        d = [b - a for a, b in zip(self.start, self.end, strict=True)]
        return {"thread_cpu_ms": d[0] * 1e3, "nivcsw": d[1], "nvcsw": d[2], "minflt": d[3], "gc": d[4]}

    def close(self) -> None:
        self._undo()


def cause(row: dict) -> str:
    if row["gc"]:
        return "gc"
    if row["minflt"]:
        return "faults"
    if row["nivcsw"]:
        return "preempted"
    if row["nvcsw"]:
        return "blocked"
    if row["cpu_ms"] > 1.5 * row["thread_cpu_ms"]:
        return "off-cpu"
    return "slow on cpu"


def sample(ctx, case: str, runner, watched: Watched, frames: int) -> list[dict]:
    from wgpurender.bench import frames as bf

    bf.settle_garbage()
    if hasattr(runner, "collect_gpu"):
        runner.collect_gpu()
    bf.warm_up(runner, 2)
    rows = []
    with bf.frames_without_gc():
        for i in range(frames):
            cpu_ms, _ = runner.frame()
            rows.append({"case": case, "frame": i, "cpu_ms": cpu_ms, **watched.delta(),
                         "threads": "+".join(sorted(t.name for t in threading.enumerate()))})
    watched.close()
    return rows


def main(out: Path, frames: int) -> None:
    from wgpurender.bench.frames import WgpuStageRunner
    from wgpurender.bench.scene import SceneRunner
    from wgpurender.core.files.assets import resolve_scene
    from wgpurender.wgpu_path.device.context import get_context

    ctx = get_context()
    rows = []
    for name, size in STAGES:
        runner = WgpuStageRunner(ctx, name, size)
        rows += sample(ctx, f"{name} {size[0]}x{size[1]}", runner, Watched(ctx, runner, "record"), frames)
    for name, size in SCENES:
        runner = SceneRunner(ctx, resolve_scene(name), size)
        rows += sample(ctx, f"scene {name} {size[0]}x{size[1]}", runner, Watched(ctx, runner.renderer, "record"),
                       frames)
    for case in dict.fromkeys(r["case"] for r in rows):
        mine = [r for r in rows if r["case"] == case]
        med = statistics.median(r["cpu_ms"] for r in mine)
        slow = [r for r in mine if r["cpu_ms"] > 2 * med]
        for r in mine:
            r["slow"] = int(r in slow)
            r["cause"] = cause(r) if r in slow else ""
        counts = {c: sum(r["cause"] == c for r in slow) for c in dict.fromkeys(r["cause"] for r in slow)}
        print(f"{case:28s} cpu med {med:.3f} ms, thread cpu med "
              f"{statistics.median(r['thread_cpu_ms'] for r in mine):.3f}; > 2x: {len(slow)} of {len(mine)} {counts}; "
              f"frames with faults {sum(r['minflt'] > 0 for r in mine)}, preempted "
              f"{sum(r['nivcsw'] > 0 for r in mine)}, blocked {sum(r['nvcsw'] > 0 for r in mine)}")
    print("python threads:", rows[-1]["threads"])
    write_rows(out, rows, digits=4)


if __name__ == "__main__":
    main(Path(sys.argv[1]), int(sys.argv[2]) if len(sys.argv) > 2 else 200)
