"""The distinct-mesh load of `bench perf`'s scene-scale family, timed alone: N cube files, each its own model, from
the scene file to the first frame read back (bench/scale.py's ``load_ms``). Whichever wgpurender is first on
PYTHONPATH is timed, so one call on one machine can time two trees (the device run times main's and this branch's).

    python benchmarks/load_compare.py LABEL N OUT.csv [cold|warm]
        (appends: label, n, parse cache, wall ms, process CPU ms, worker processes)

``cold``: the parse cache (core/models/obj_cached.py) starts empty ($XDG_CACHE_HOME is pointed at a new
temporary folder: the machine's own cache is never read or written); ``warm``: the same folder after one
untimed load of the same scene. The OS file cache is warm in both (the files were just written). A tree without
the parse cache reads the same either way.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

from wgpurender.bench import scale
from wgpurender.bench.scene import SceneRunner
from wgpurender.wgpu_path.device.context import get_context

SIZE = (800, 600)


def main() -> int:
    label, n, out = sys.argv[1], int(sys.argv[2]), Path(sys.argv[3])
    mode = sys.argv[4] if len(sys.argv) > 4 else "cold"
    if mode not in ("cold", "warm"):
        print(f"cache mode {mode!r}: give cold or warm", file=sys.stderr)
        return 2
    ctx = get_context()
    with tempfile.TemporaryDirectory() as tmp, tempfile.TemporaryDirectory() as cache:
        os.environ["XDG_CACHE_HOME"] = cache  # never the machine's own cache
        SceneRunner(ctx, scale.distinct_scene(Path(tmp), 4, SIZE), SIZE).frame(readback=True)  # shaders, imports
        scene = scale.distinct_scene(Path(tmp), n, SIZE)
        if mode == "warm":
            SceneRunner(ctx, scene, SIZE).frame(readback=True)  # fills the parse cache
        wall, cpu = time.perf_counter(), time.process_time()
        runner = SceneRunner(ctx, scene, SIZE)
        runner.frame(readback=True)
        wall, cpu = (time.perf_counter() - wall) * 1e3, (time.process_time() - cpu) * 1e3
    workers = getattr(runner.renderer.plan, "mesh_workers", 0)
    new = not out.exists()
    with out.open("a") as f:
        if new:
            f.write("tree,distinct_meshes,parse_cache,load_wall_ms,load_process_cpu_ms,mesh_workers\n")
        f.write(f"{label},{n},{mode},{wall:.1f},{cpu:.1f},{workers}\n")
    print(f"{label}: {n} distinct meshes load in {wall:.0f} ms ({cpu:.0f} ms process CPU; parse cache {mode}, "
          f"{workers} worker processes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
