"""The load's per-model steps in the renderer, each timed alone (issue 31.3's second pass: steps changed after its
one H100 call are measured here, tree against tree, in one run).

    python benchmarks/load_steps_probe.py SCENE.toml LABEL

After one load of SCENE (its meshes in this process), with the collector off as during a load, the minimum of 5
repetitions of: the scene pass's object blocks, material slots and draw state (``_setup_uniforms`` +
``_setup_draws``); the plan's batching (``batches.batch_draws``); the meshes' upload into the shared buffers with
every mesh already loaded (``SceneResources.upload_meshes``); unpacking 2,000 workers' meshes in this process
(``mesh_workers._take``, scaled to 10k). Whichever wgpurender is first on PYTHONPATH is timed.
"""

from __future__ import annotations

import gc
import sys
import time
from pathlib import Path

from wgpurender.core.models import mesh_workers, obj_cached
from wgpurender.core.plan import batches, resolve_plan
from wgpurender.core.scene import load_scene
from wgpurender.wgpu_path.device.context import get_context
from wgpurender.wgpu_path.scene.frame import SceneRenderer
from wgpurender.wgpu_path.scene.resources import SceneResources


def best(fn, scale: float = 1.0) -> float:
    times = []
    for _ in range(5):
        start = time.perf_counter()
        fn()
        times.append((time.perf_counter() - start) * scale)
    return min(times) * 1e3


def main() -> int:
    scene_path, label = Path(sys.argv[1]), sys.argv[2]
    ctx = get_context()
    scene = load_scene(scene_path)
    plan = resolve_plan(scene, ctx.adapter_facts(), size=(800, 600))
    renderer = SceneRenderer(ctx, scene, plan)
    loaded, draws, scene_pass = renderer.resources.meshes._meshes, plan.scene_pass.draws, renderer.scene_pass
    blend = {p.key: p.blend for p in plan.pipelines}
    jobs = [(d.model_path, False) for d in draws[:2000]]
    chunk = mesh_workers.read_chunk(jobs, obj_cached.folder())

    def upload():
        fresh = SceneResources(ctx, plan)
        fresh.meshes._meshes = dict(loaded)
        fresh.upload_meshes(draws)

    gc.disable()
    rows = {"uniforms + draws": best(lambda: (scene_pass._setup_uniforms(), scene_pass._setup_draws())),
            "batch_draws": best(lambda: batches.batch_draws(list(draws), blend)),
            "upload (meshes loaded)": best(upload),
            "unpack 10k workers' meshes": best(lambda: mesh_workers._take(jobs, chunk, {}), len(draws) / len(jobs))}
    print(label, ", ".join(f"{k} {v:.1f} ms" for k, v in rows.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
