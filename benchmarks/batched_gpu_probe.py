"""Why bench perf's ``batched/N`` took 5.7x ``instanced/N``'s GPU time on the H100 (bench7's call, 19:45 UTC:
0.616 against 0.107 ms at 1k, 1.564 against 0.273 at 10k) when lavapipe draws both the same: the same plan, the
same one ``draw_indexed`` in the bundle, the same pixels. One process draws the three scenes of each count in
interleaved rounds (bench/frames.py's measure_interleaved, the order flipped each round, instanced NOT first in
every round), and prints per scene: the median GPU ms, the plan's draws and instance counts, a hash of the
object blocks the scene pass uploads and of the vertex and index bytes drawn, and whether the image equals
instanced's.

    python benchmarks/batched_gpu_probe.py OUT.csv [N,N,...]
    python benchmarks/batched_gpu_probe.py --alone SCENE N OUT.csv
        one scene alone in this process (bench perf's order: loaded, then measured as scene-scale measures it),
        a row appended to OUT.csv with the SM clock before and after (nvidia-smi, where there is one)

The first call (the late session's, 20:05 UTC on the H100) read the three scenes of a count alike when
interleaved (1k: 0.40-0.42 ms; 10k: 1.56-1.60), where bench perf's rows, measured one scene after another in
one process, read instanced 0.107 / 0.273 ms and batched 0.616 / 1.564: ``--alone`` runs each scene in a fresh
process, in either order, to tell the scene from the order.
"""

from __future__ import annotations

import csv
import hashlib
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

import numpy as np

from wgpurender.bench import scale
from wgpurender.bench.frames import measure_interleaved
from wgpurender.bench.scene import SceneRunner
from wgpurender.bench.sm_clock import sm_clock
from wgpurender.wgpu_path.device.context import get_context
from wgpurender.wgpu_path.device.targets import read_texture

SIZE = (800, 600)


def _digest(data) -> str:
    return hashlib.sha256(bytes(memoryview(np.ascontiguousarray(data)).cast("B"))).hexdigest()[:12]


def facts(runner: SceneRunner) -> dict:
    """The plan's draws and the bytes the GPU reads, hashed (the scene pass keeps its object blocks)."""
    from wgpurender.core.plan.batches import instance_blocks

    draws = runner.renderer.plan.scene_pass.draws
    blocks = instance_blocks(draws)
    return {"draws": len(draws), "instances": sum(d.instance_count for d in draws),
            "objects": _digest(blocks), "object_bytes": np.asarray(blocks).nbytes,
            "instance_data": runner.renderer.plan.instance_data}


def alone(name: str, n: int, out: Path) -> int:
    """One scene in this process, measured as bench/scale.py's bench_case measures it (frames.measure)."""
    from wgpurender.bench.frames import measure

    ctx = get_context()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        texture = folder / "brick_albedo.png"
        shutil.copy(scale.brick_texture(), texture)
        make = {"batched": scale.batched_scene, "distinct": scale.distinct_scene, "instanced": scale.instanced_scene}
        runner = SceneRunner(ctx, make[name](folder, n, SIZE, texture), SIZE)
        runner.frame(readback=True)
        before = sm_clock("")
        samples = measure(runner, 100)
        row = {"n": n, "scene": name, "gpu_ms": statistics.median(samples.gpu),
               "cpu_ms": statistics.median(samples.cpu), "sm_mhz_before": before, "sm_mhz_after": sm_clock(""),
               **facts(runner)}
    print(row, flush=True)
    new = not out.exists()
    with open(out, "a", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(row))
        if new:
            w.writeheader()
        w.writerow(row)
    return 0


def main() -> int:
    if sys.argv[1] == "--alone":
        return alone(sys.argv[2], int(sys.argv[3]), Path(sys.argv[4]))
    out = Path(sys.argv[1])
    counts = [int(n) for n in (sys.argv[2] if len(sys.argv) > 2 else "1000,10000").split(",")]
    ctx = get_context()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        texture = folder / "brick_albedo.png"
        shutil.copy(scale.brick_texture(), texture)
        for n in counts:
            scenes = {"batched": scale.batched_scene(folder, n, SIZE, texture),
                      "distinct": scale.distinct_scene(folder, n, SIZE, texture),
                      "instanced": scale.instanced_scene(folder, n, SIZE, texture)}
            runners = {name: SceneRunner(ctx, path, SIZE) for name, path in scenes.items()}
            images = {}
            for name, r in runners.items():
                r.frame()
                images[name] = read_texture(ctx, r.target)
            samples = measure_interleaved(runners, 200, rounds=8)
            for name, r in runners.items():
                f = facts(r)
                same = bool(np.array_equal(images[name], images["instanced"]))
                row = {"n": n, "scene": name, "gpu_ms": statistics.median(samples[name].gpu),
                       "cpu_ms": statistics.median(samples[name].cpu), "same_image_as_instanced": same, **f}
                rows.append(row)
                print(row, flush=True)
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
