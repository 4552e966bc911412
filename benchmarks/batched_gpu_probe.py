"""Why bench perf's ``batched/N`` took 5.7x ``instanced/N``'s GPU time on the H100 (bench7's call, 19:45 UTC:
0.616 against 0.107 ms at 1k, 1.564 against 0.273 at 10k) when lavapipe draws both the same: the same plan, the
same one ``draw_indexed`` in the bundle, the same pixels. One process draws the three scenes of each count in
interleaved rounds (bench/frames.py's measure_interleaved, the order flipped each round, instanced NOT first in
every round), and prints per scene: the median GPU ms, the plan's draws and instance counts, a hash of the
object blocks the scene pass uploads and of the vertex and index bytes drawn, and whether the image equals
instanced's.

    python benchmarks/batched_gpu_probe.py OUT.csv [N,N,...]
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


def main() -> int:
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
