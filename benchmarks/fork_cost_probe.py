"""What starting the mesh workers costs in a process that holds a GPU device (issue 31.3: a 10k-file load forks up
to 16 workers from the renderer's process, whose page tables grow with the driver's mappings).

    python benchmarks/fork_cost_probe.py [WORKERS]

Prints, after a device is made and a small scene drawn: the process's resident size, the wall ms of WORKERS bare
``os.fork()`` + ``_exit`` + wait, one after another (what the pool's start pays per worker, at least), and of a
``ProcessPoolExecutor`` of WORKERS forked workers mapping one trivial task each (start to results).
"""

from __future__ import annotations

import multiprocessing
import os
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from wgpurender.bench import scale
from wgpurender.bench.scene import SceneRunner
from wgpurender.wgpu_path.device.context import get_context


def _one(k: int) -> int:
    return k


def main() -> int:
    workers = int(sys.argv[1]) if len(sys.argv) > 1 else 16
    ctx = get_context()
    with tempfile.TemporaryDirectory() as tmp:
        SceneRunner(ctx, scale.distinct_scene(Path(tmp), 4, (800, 600)), (800, 600)).frame(readback=True)
    rss = int(Path("/proc/self/statm").read_text().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
    start = time.perf_counter()
    for _ in range(workers):
        pid = os.fork()
        if pid == 0:
            os._exit(0)
        os.waitpid(pid, 0)
    forks = (time.perf_counter() - start) * 1e3
    start = time.perf_counter()
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork")) as pool:
        assert list(pool.map(_one, range(workers))) == list(range(workers))
    pool_ms = (time.perf_counter() - start) * 1e3
    print(f"resident {rss:.0f} MiB; {workers} bare forks {forks:.1f} ms ({forks / workers:.2f} ms each); "
          f"a pool of {workers} forked workers, one task each: {pool_ms:.1f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
