"""The distinct-mesh load of `bench perf`'s scene-scale family, timed alone: N cube files, each its own model, from
the scene file to the first frame read back (bench/scale.py's ``load_ms``), and its phases. Whichever wgpurender
is first on PYTHONPATH is timed, so one call on one machine can time two trees (the device run times main's and
this branch's).

    python benchmarks/load_compare.py LABEL N OUT.csv [cold|warm] [KNOB=VALUE ...]
        appends: label, n, parse cache, knobs, wall ms, process CPU ms, worker processes, and the wall ms of
        the phases: scene file (load_scene), plan (resolve_plan), renderer (meshes, buffers, pipelines, the
        bundle), first frame (record, submit, read back)

``cold``: the parse cache (core/models/obj_cached.py) starts empty ($XDG_CACHE_HOME is pointed at a new
temporary folder: the machine's own cache is never read or written); ``warm``: the same folder after one
untimed load of the same scene. The OS file cache is warm in both (the files were just written). A tree without
the parse cache reads the same either way. ``KNOB=VALUE``: plan knobs (e.g. ``mesh_workers=off``); a tree that
lacks the knob refuses it.
"""

from __future__ import annotations

import itertools
import os
import sys
import tempfile
import time
from pathlib import Path

from wgpurender.bench import scale
from wgpurender.bench.scene import SceneRunner
from wgpurender.core.plan import resolve_plan
from wgpurender.core.scene import load_scene
from wgpurender.wgpu_path.device.context import get_context
from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.scene.frame import SceneRenderer

SIZE = (800, 600)
PHASES = ("scene_ms", "plan_ms", "renderer_ms", "frame_ms")


def timed_load(ctx, scene: Path, knobs: dict) -> tuple[list[float], int]:
    """The wall ms of each phase of load_renderer's way (scene file, plan, renderer) and the first frame."""
    marks = [time.perf_counter()]
    loaded = load_scene(scene)
    marks.append(time.perf_counter())
    plan = resolve_plan(loaded, ctx.adapter_facts(), size=SIZE, **knobs)
    marks.append(time.perf_counter())
    renderer = SceneRenderer(ctx, loaded, plan)
    marks.append(time.perf_counter())
    run_frame(ctx, renderer.record, renderer.create_output(), 0.0, label="load-compare", read_back=True)
    marks.append(time.perf_counter())
    return [(b - a) * 1e3 for a, b in itertools.pairwise(marks)], getattr(renderer.plan, "mesh_workers", 0)


def main() -> int:
    label, n, out = sys.argv[1], int(sys.argv[2]), Path(sys.argv[3])
    mode = sys.argv[4] if len(sys.argv) > 4 else "cold"
    knobs = dict(arg.split("=", 1) for arg in sys.argv[5:])
    if mode not in ("cold", "warm"):
        print(f"cache mode {mode!r}: give cold or warm", file=sys.stderr)
        return 2
    ctx = get_context()
    with tempfile.TemporaryDirectory() as tmp, tempfile.TemporaryDirectory() as cache:
        os.environ["XDG_CACHE_HOME"] = cache  # never the machine's own cache
        SceneRunner(ctx, scale.distinct_scene(Path(tmp), 4, SIZE), SIZE).frame(readback=True)  # shaders, imports
        scene = scale.distinct_scene(Path(tmp), n, SIZE)
        if mode == "warm":
            timed_load(ctx, scene, knobs)  # fills the parse cache
        wall, cpu = time.perf_counter(), time.process_time()
        phases, workers = timed_load(ctx, scene, knobs)
        wall, cpu = (time.perf_counter() - wall) * 1e3, (time.process_time() - cpu) * 1e3
    new = not out.exists()
    shown = " ".join(f"{k}={v}" for k, v in knobs.items()) or "-"
    with out.open("a") as f:
        if new:
            f.write("tree,distinct_meshes,parse_cache,knobs,load_wall_ms,load_process_cpu_ms,mesh_workers,"
                    + ",".join(PHASES) + "\n")
        f.write(f"{label},{n},{mode},{shown},{wall:.1f},{cpu:.1f},{workers},"
                + ",".join(f"{p:.1f}" for p in phases) + "\n")
    split = ", ".join(f"{k} {p:.0f}" for k, p in zip(PHASES, phases, strict=True))
    print(f"{label}: {n} distinct meshes load in {wall:.0f} ms ({cpu:.0f} ms process CPU; parse cache {mode}, "
          f"knobs {shown}, {workers} worker processes; {split})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
