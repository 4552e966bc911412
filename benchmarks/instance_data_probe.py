"""The instance_data check on one backend (issue 31's GL regression): ``python benchmarks/instance_data_probe.py
vulkan|opengl [COUNTS...]``.

Prints the adapter (info, the limits and features the plan reads), the plan's instance_data and culling for an
instanced scene of bench/scale.py, the first line of what each way gives on a small scene (an error there is the
regression), and frame / CPU / GPU medians of both ways (storage, vertex) with culling off and auto, measured with
bench/frames.measure (warm-up until stable, the garbage collector paused). One wgpu instance per process and
backend: run it once per backend.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

LIMITS = ("max-storage-buffers-per-shader-stage", "max-compute-invocations-per-workgroup", "max-vertex-attributes",
          "max-vertex-buffers")
SIZE = (800, 600)


def _runner(ctx, path: Path, knobs: dict):
    from wgpurender.bench.scene import SceneRunner
    from wgpurender.wgpu_path.scene import load_renderer

    runner = SceneRunner(ctx, path, SIZE)
    runner.renderer = load_renderer(path, ctx, size=SIZE, knobs=knobs)
    runner.target = runner.renderer.create_output()
    return runner


def main(backend: str, counts: list[int]) -> None:
    import numpy as np

    from wgpurender.bench.frames import measure
    from wgpurender.bench.scale import instanced_scene
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene import load_renderer, render_frame

    ctx = get_context(backend)
    info = ctx.adapter.info
    print(f"adapter: {info['device']} | {info['backend_type']} | {info['adapter_type']} | {info['description']}")
    print("limits:", {k: ctx.adapter.limits[k] for k in LIMITS})
    print("features:", sorted(f for f in ctx.adapter.features if "storage" in f or "instance" in f))
    print("facts:", ctx.adapter_facts())
    with tempfile.TemporaryDirectory() as tmp:
        small = instanced_scene(Path(tmp), 16, (96, 64))
        images = {}
        for way in ("auto", "storage", "vertex"):
            try:
                r = load_renderer(small, ctx, knobs={"instance_data": way})
                images[way] = render_frame(ctx, r, r.create_output())[0]
                mean = images[way].mean()
                print(f"16 copies, instance_data {way} -> {r.plan.instance_data}: rendered, mean {mean:.2f}")
            except Exception as err:  # noqa: BLE001  (the probe reports whatever the way raises)
                print(f"16 copies, instance_data {way}: {type(err).__name__}: {' | '.join(str(err).splitlines()[:4])}")
        if "storage" in images and "vertex" in images:
            print("storage vs vertex: max difference", int(np.abs(images["storage"].astype(int)
                                                                  - images["vertex"].astype(int)).max()))
        for n in counts:
            path = instanced_scene(Path(tmp), n, SIZE)
            plan = load_renderer(path, ctx, size=(32, 24)).plan
            print(f"{n} copies, auto plan: instance_data {plan.instance_data}, culling {plan.setting('culling')}")
            for way in ("storage", "vertex"):
                for culling in ("off", "auto"):
                    try:
                        runner = _runner(ctx, path, {"instance_data": way, "culling": culling})
                        rows = measure(runner, 40).results("instance-data", f"{way}/{n}", "wgpu", SIZE)
                    except Exception as err:  # noqa: BLE001
                        print(f"  {way:7s} culling {culling:4s}: {type(err).__name__}: {str(err).splitlines()[0]}")
                        continue
                    got = runner.renderer.plan.setting("culling")
                    text = ", ".join(f"{r.metric} {r.median:.3f}" for r in rows)
                    print(f"  {way:7s} culling {culling:4s} ({got}): {text}")


if __name__ == "__main__":
    main(sys.argv[1], [int(a) for a in sys.argv[2:]] or [10_000, 100_000])
