"""Where the first pixel's time goes, in fresh processes (issue 22.5): cProfile of a whole child (imports,
context, set-up, first frame) on each path, and ``python -X importtime`` of the wgpu context.

    python benchmarks/first_pixel_profile.py [OUT_DIR]

Writes first-pixel-profile-{wgpu,raw}.txt and wgpu-importtime.txt into OUT_DIR (default .). The wgpu child runs
twice first so the caches a second run of the same command has (the cached wgpu.h parse, SPIR-V) are warm.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

CHILD = r"""
import cProfile, io, pstats, sys, time
t0 = time.perf_counter()
pr = cProfile.Profile()
pr.enable()
from wgpurender.bench.startup_child import child
marks = child(sys.argv[1], "3d", (800, 600), t0)
pr.disable()
s = io.StringIO()
st = pstats.Stats(pr, stream=s)
st.sort_stats("cumulative").print_stats(45)
st.sort_stats("tottime").print_stats(25)
print(marks)
print(s.getvalue())
"""


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, WGPURENDER_VALIDATION="0")
    env.setdefault("XDG_RUNTIME_DIR", "/tmp")
    from wgpurender.bench.startup_child import LAUNCH

    for path in ("wgpu", "raw"):
        for _ in range(2):  # warm what a second run has
            subprocess.run([sys.executable, "-c", LAUNCH, path, "3d", "800x600"], env=env, capture_output=True,
                           timeout=300)
        proc = subprocess.run([sys.executable, "-c", CHILD, path], env=env, capture_output=True, text=True,
                              timeout=300)
        (out / f"first-pixel-profile-{path}.txt").write_text(proc.stdout + proc.stderr[-3000:])
    proc = subprocess.run([sys.executable, "-X", "importtime", "-c",
                           "from wgpurender.wgpu_path.device.context import get_context; get_context()"],
                          env=env, capture_output=True, text=True, timeout=300)
    lines = [ln for ln in proc.stderr.splitlines() if ln.startswith("import time:")]
    rows = sorted(lines[1:], key=lambda ln: -int(ln.split("|")[1]))[:60]
    (out / "wgpu-importtime.txt").write_text("\n".join([lines[0] if lines else "", *rows]) + "\n")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("."))
