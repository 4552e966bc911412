"""The distinct-mesh load of `bench perf`'s scene-scale family, timed alone: N cube files, each its own model, from
the scene file to the first frame read back (bench/scale.py's ``load_ms``). Whichever wgpurender is first on
PYTHONPATH is timed, so one call on one machine can time two trees (the device run times main's and this branch's).

    python benchmarks/load_compare.py LABEL N OUT.csv   (appends: label, n, wall ms, process CPU ms)
"""

from __future__ import annotations

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
    ctx = get_context()
    with tempfile.TemporaryDirectory() as tmp:
        SceneRunner(ctx, scale.distinct_scene(Path(tmp), 4, SIZE), SIZE).frame(readback=True)  # shaders, imports
        scene = scale.distinct_scene(Path(tmp), n, SIZE)
        wall, cpu = time.perf_counter(), time.process_time()
        SceneRunner(ctx, scene, SIZE).frame(readback=True)
        wall, cpu = (time.perf_counter() - wall) * 1e3, (time.process_time() - cpu) * 1e3
    new = not out.exists()
    with out.open("a") as f:
        if new:
            f.write("tree,distinct_meshes,load_wall_ms,load_process_cpu_ms\n")
        f.write(f"{label},{n},{wall:.1f},{cpu:.1f}\n")
    print(f"{label}: {n} distinct meshes load in {wall:.0f} ms ({cpu:.0f} ms process CPU)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
