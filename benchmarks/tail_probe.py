"""What the slow frames of bench perf's frame rows are (issue 31.4: p99 <= 2x the median): each timed frame of a
few cases, with where it sits, as ``bench perf``'s frames family times them (bench/frames.py: 4 alternating rounds,
the first half of each round's frames followed by a frame with readback, which is not a sample).

    python benchmarks/tail_probe.py [OUT.csv] [FRAMES]

Writes one row per timed frame (case, path, round, position in the round, whether the frame before it read the
image back, cpu_ms, frame_ms) and prints, per case and path: the median and p99 of cpu_ms and frame_ms, and the
median cpu_ms of the frames that follow a readback frame, of those that do not, and of each round's first frame,
and where the frames over 2x the median cpu_ms sit.
"""

from __future__ import annotations

import csv
import statistics
import sys
from pathlib import Path

CASES = (("msaa-post", (1920, 1080)), ("textured", (800, 600)), ("clear", (800, 600)), ("clear-pass", (800, 600)),
         ("triangle", (1280, 720)))
ROUNDS = 4


def p99(values: list[float]) -> float:
    from wgpurender.wgpu_path.device.timing import Stats

    return Stats.of(values).p99


def main(out: Path | None, frames: int) -> None:
    from wgpurender.bench.frames import RawStageRunner, WgpuStageRunner, measure_interleaved
    from wgpurender.wgpu_path.device.context import get_context

    ctx = get_context()
    rows = []
    rb = max(3, frames // 2)
    per, rb_per = max(1, frames // ROUNDS), -(-rb // ROUNDS)
    for name, size in CASES:
        with RawStageRunner(name, size) as raw:
            samples = measure_interleaved({"wgpu": WgpuStageRunner(ctx, name, size), "raw": raw}, frames, rb)
        for path, s in samples.items():
            for i, (cpu, frame) in enumerate(zip(s.cpu, s.frame, strict=True)):
                k, j = divmod(i, per)
                rows.append({"case": f"{name} {size[0]}x{size[1]}", "path": path, "round": k, "position": j,
                             "after_readback": int(0 < j <= rb_per), "cpu_ms": round(cpu, 4),
                             "frame_ms": round(frame, 4)})
    for key in dict.fromkeys((r["case"], r["path"]) for r in rows):
        mine = [r for r in rows if (r["case"], r["path"]) == key]
        cpu = [r["cpu_ms"] for r in mine]
        frame = [r["frame_ms"] for r in mine]
        after = [r["cpu_ms"] for r in mine if r["after_readback"]]
        plain = [r["cpu_ms"] for r in mine if not r["after_readback"] and r["position"]]
        first = [r["cpu_ms"] for r in mine if r["position"] == 0]
        slow = [r for r in mine if r["cpu_ms"] > 2 * statistics.median(cpu)]
        where = {"after readback": sum(r["after_readback"] for r in slow),
                 "round's first": sum(r["position"] == 0 for r in slow)}
        where["other"] = len(slow) - sum(where.values())
        print(f"{key[0]:22s} {key[1]:4s} cpu med {statistics.median(cpu):.3f} p99 {p99(cpu):.3f} "
              f"({p99(cpu) / statistics.median(cpu):.1f}x) | frame med {statistics.median(frame):.3f} "
              f"p99 {p99(frame):.3f} ({p99(frame) / statistics.median(frame):.1f}x) | cpu after readback "
              f"{statistics.median(after):.3f}, not {statistics.median(plain):.3f}, round's first "
              f"{statistics.median(first):.3f} | cpu > 2x median: {len(slow)} of {len(cpu)} ({where})")
    if out:
        with out.open("w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else None, int(sys.argv[2]) if len(sys.argv) > 2 else 100)
