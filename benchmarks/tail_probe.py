"""What the slow frames of bench perf's frame rows are (issue 31.4: p99 <= 2x the median): each timed frame of a
few cases, with where it sits, timed the way ``bench perf``'s frames family times them now (bench/frames.py's
``measure_interleaved``) and the way it did before issue 31.4's change ("old": the garbage collected and the
timestamps read between the warm-up and the first sample; a readback frame after each of the first half of the
samples), same process, same runners.

    python benchmarks/tail_probe.py [OUT.csv] [FRAMES]

Writes one row per timed frame (case, path, method, round, position in the round, whether the frame before it read
the image back, cpu_ms, frame_ms) and prints, per case, path and method: the median and p99/median of cpu_ms and
frame_ms, and where the frames over 2x the median cpu_ms sit (right after a readback frame, first in a round, other).
"""

from __future__ import annotations

import statistics
import sys
from pathlib import Path

from probe_csv import write_rows

CASES = (("msaa-post", (1920, 1080)), ("textured", (800, 600)), ("clear", (800, 600)), ("clear-pass", (800, 600)),
         ("triangle", (1280, 720)))
ROUNDS = 4


def p99(values: list[float]) -> float:
    from wgpurender.wgpu_path.device.timing import Stats

    return Stats.of(values).p99


def old_measure(runner, frames: int, warmup: int, readback_frames: int):
    """bench/frames.py's measure before issue 31.4's change (GPU times left out)."""
    from wgpurender.bench import frames as bf

    bf.warm_up(runner, warmup)
    bf.settle_garbage()
    collect = getattr(runner, "collect_gpu", None)
    if collect is not None:
        collect()
    samples = bf.Samples()
    with bf.frames_without_gc():
        for i in range(frames):
            frame_ms, cpu_ms, _ = bf._timed(runner)
            samples.frame.append(frame_ms)
            samples.cpu.append(cpu_ms)
            if i < readback_frames:
                bf._timed(runner, readback=True)
    return samples


def old_interleaved(runners: dict, frames: int, readback_frames: int) -> dict:
    from wgpurender.bench.frames import Samples

    out = {name: Samples() for name in runners}
    per, rb = max(1, frames // ROUNDS), max(0, -(-readback_frames // ROUNDS))
    for k in range(ROUNDS):
        for name in (list(runners) if k % 2 == 0 else list(runners)[::-1]):
            out[name].extend(old_measure(runners[name], per, 2 if k == 0 else 1, rb))
    return out


def main(out: Path | None, frames: int) -> None:
    from wgpurender.bench.frames import RawStageRunner, WgpuStageRunner, measure_interleaved
    from wgpurender.wgpu_path.device.context import get_context

    ctx = get_context()
    rows = []
    rb = max(3, frames // 2)
    per, rb_per = max(1, frames // ROUNDS), -(-rb // ROUNDS)
    for name, size in CASES:
        with RawStageRunner(name, size) as raw:
            runners = {"wgpu": WgpuStageRunner(ctx, name, size), "raw": raw}
            for method, samples in (("now", measure_interleaved(runners, frames, rb)),
                                    ("old", old_interleaved(runners, frames, rb))):
                for path, s in samples.items():
                    for i, (cpu, frame) in enumerate(zip(s.cpu, s.frame, strict=True)):
                        k, j = divmod(i, per)
                        rows.append({"case": f"{name} {size[0]}x{size[1]}", "path": path, "method": method,
                                     "round": k, "position": j,
                                     "after_readback": int(method == "old" and 0 < j <= rb_per),
                                     "cpu_ms": round(cpu, 4), "frame_ms": round(frame, 4)})
    for key in dict.fromkeys((r["case"], r["path"], r["method"]) for r in rows):
        mine = [r for r in rows if (r["case"], r["path"], r["method"]) == key]
        cpu, frame = [r["cpu_ms"] for r in mine], [r["frame_ms"] for r in mine]
        slow = [r for r in mine if r["cpu_ms"] > 2 * statistics.median(cpu)]
        where = {"after readback": sum(r["after_readback"] for r in slow),
                 "round's first": sum(r["position"] == 0 for r in slow)}
        where["other"] = len(slow) - sum(where.values())
        print(f"{key[0]:20s} {key[1]:4s} {key[2]:3s} cpu med {statistics.median(cpu):.3f} p99 "
              f"{p99(cpu) / statistics.median(cpu):.1f}x | frame med {statistics.median(frame):.3f} p99 "
              f"{p99(frame) / statistics.median(frame):.1f}x | cpu > 2x median: {len(slow)} ({where})")
    if out:
        write_rows(out, rows)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else None, int(sys.argv[2]) if len(sys.argv) > 2 else 100)
