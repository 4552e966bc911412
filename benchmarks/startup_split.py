"""Where the wgpu path's first pixel goes, and what making the device on a thread (context.start_context) buys
(issue 31.5): fresh processes, interleaved, medians per phase.

    python benchmarks/startup_split.py [RUNS] [OUT.csv]

Variants (each a fresh process running the startup family's steps for stage 3d at 800x600, bytecode cached after
one warming run of each):

- ``wgpu early``: as ``bench perf --only startup`` times it (bench/startup.py): the device is started on a thread
  before the renderer's modules are imported, as ``wgpurender render`` does;
- ``wgpu in order``: the same steps with the device made on the main thread after the imports (main before
  issue 31.5's change);
- ``wgpu early, 5 ms switch``: early, with Python's default thread switch interval kept while the device is made
  (context.EARLY_SWITCH_S lowers it to 0.5 ms: the device thread makes ~140 short native calls, each of which may
  wait for the GIL while the main thread imports);
- ``raw``: the raw path's child, the reference.

Phases: ``import_ms`` (to the stage class), ``context_ms`` (what is left of making the device), ``make_ms`` (how
long making it took, on whichever thread), ``setup_ms``, ``record_submit_ms`` and ``read_ms`` (the first frame's
record + submit, then its readback wait), ``total_ms`` (process start to the first pixels).
"""

from __future__ import annotations

import csv
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

CHILD = r"""
import json, sys, time
T0 = time.perf_counter()
variant = sys.argv[1]
m = {}
if variant == "raw":
    from wgpurender.bench.startup import _child
    out = _child("raw", "3d", (800, 600))
    print(json.dumps(out))
    raise SystemExit
from wgpurender.wgpu_path.device import context as c
if "switch" in variant:
    c.EARLY_SWITCH_S = 0.005
made = {}
real = c._make_context
def timed(backend):
    t = time.perf_counter(); ctx = real(backend); made["ms"] = (time.perf_counter() - t) * 1e3; return ctx
c._make_context = timed
if "early" in variant:
    c.start_context()
from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.device.targets import create_target
from wgpurender.wgpu_path.stages import get_stage
cls = get_stage("3d")
m["import_ms"] = time.perf_counter()
ctx = c.get_context()
m["context_ms"] = time.perf_counter()
st = cls(ctx, cls.default_format, None)
st.resize((800, 600))
target = create_target(ctx, (800, 600), st.format)
m["setup_ms"] = time.perf_counter()
enc = ctx.device.create_command_encoder()
st.record(enc, target, 0.0)
from wgpurender.wgpu_path.device.frame_loop import _readback
rb = _readback(ctx)
rb.record(enc, target)
ctx.queue.submit([enc.finish()])
m["record_submit_ms"] = time.perf_counter()
rb.read()
m["read_ms"] = time.perf_counter()
out, last = {}, T0
for k, v in m.items():
    out[k] = (v - last) * 1e3
    last = v
out["make_ms"] = made["ms"]
out["total_ms"] = (last - T0) * 1e3
print(json.dumps(out))
"""

VARIANTS = ("wgpu early", "wgpu in order", "wgpu early, 5 ms switch", "raw")


def run(variant: str, env: dict) -> dict:
    proc = subprocess.run([sys.executable, "-c", CHILD, variant], capture_output=True, text=True, env=env,
                          timeout=300)
    if proc.returncode:
        raise RuntimeError(proc.stderr[-2000:])
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(runs: int, out: Path | None) -> None:
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, WGPURENDER_VALIDATION="0", PYTHONPYCACHEPREFIX=str(Path(tmp) / "pyc"),
                   XDG_CACHE_HOME=str(Path(tmp) / "xdg"), MESA_SHADER_CACHE_DISABLE="true",
                   __GL_SHADER_DISK_CACHE="0")
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env.setdefault("XDG_RUNTIME_DIR", "/tmp")
        for v in VARIANTS:  # warm: bytecode, wgpu.h's parse, SPIR-V
            run(v, env)
        rows: dict[str, list[dict]] = {v: [] for v in VARIANTS}
        for _ in range(runs):
            for v in VARIANTS:
                rows[v].append(run(v, env))
    table = []
    for v, samples in rows.items():
        for key in samples[0]:
            values = [s[key] for s in samples]
            table.append({"variant": v, "phase": key, "median_ms": round(statistics.median(values), 2),
                          "min_ms": round(min(values), 2), "max_ms": round(max(values), 2), "runs": len(values)})
    for v in VARIANTS:
        print(f"{v:28s}", " ".join(f"{r['phase'][:-3]}={r['median_ms']:.1f}" for r in table if r["variant"] == v))
    raw = next(r["median_ms"] for r in table if r["variant"] == "raw" and r["phase"] == "total_ms")
    for v in VARIANTS[:-1]:
        total = next(r["median_ms"] for r in table if r["variant"] == v and r["phase"] == "total_ms")
        print(f"{v}: {total:.1f} / raw {raw:.1f} ms = {total / raw:.3f}x")
    if out:
        with out.open("w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(table[0]))
            writer.writeheader()
            writer.writerows(table)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 9, Path(sys.argv[2]) if len(sys.argv) > 2 else None)
