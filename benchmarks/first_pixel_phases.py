"""Where the wgpu path's first pixel goes after ``context.start_context`` (issue 31.5): fine marks in fresh
processes, bytecode cached, medians over RUNS children (a probe; the judged figure is bench perf's startup family).

    python benchmarks/first_pixel_phases.py [RUNS] [OUT.csv]

Each child does what the startup family's wgpu child does (bench/startup_child.py), with a mark after each step:
the driver preload started, the context module imported (wgpu-py), the device thread started (wgpu-py's backend
imported), the renderer's imports done, the device taken, the stage's buffers, layouts and groups, its shader module
(WGSL parsed by naga), its pipeline,
the target, then the first frame's record, copy, finish, submit and readback wait. The device thread's own start
and end are marked too (``thread_start``, ``thread_end``), so the critical path shows: the thread or the imports.
Two variants, interleaved: ``as-is`` (what the renderer does) and ``warm`` (a question for the GPU machine: the
device thread also writes a small buffer and submits once; does the first frame's record + submit get shorter?).
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from probe_csv import write_rows

CHILD = r"""
import time
t0 = time.perf_counter()
import json, sys
m = {}
WARM = sys.argv[1] == "warm"
def mark(k):
    m[k] = (time.perf_counter() - t0) * 1e3
from wgpurender.wgpu_path.device import driver_preload
driver_preload.start()
mark("preload_started")
from wgpurender.wgpu_path.device import context as c
mark("context_module")
real = c._make_context
def timed(backend):
    mark("thread_start")
    try:
        ctx = real(backend)
        if WARM:  # the probe's question: does first-submit work done on the thread shorten the first frame?
            buf = ctx.device.create_buffer(size=256, usage=0x0008 | 0x0040)  # COPY_DST | UNIFORM
            ctx.queue.write_buffer(buf, 0, bytes(256))
            enc = ctx.device.create_command_encoder()
            ctx.queue.submit([enc.finish()])
            ctx.wait_idle()
            mark("warmed")
        return ctx
    finally:
        mark("thread_end")
c._make_context = timed
c.start_context()
mark("start_context_returned")
from wgpurender.wgpu_path.device.frame_loop import _readback
from wgpurender.wgpu_path.device.targets import create_target
from wgpurender.wgpu_path.stages import get_stage
cls = get_stage("3d")
mark("imports")
import wgpurender.wgpu_path.stages.cube3d as cube3d
real_module = cube3d.create_shader_module
def module(*args, **kwargs):
    mark("buffers_groups_layout")
    try:
        return real_module(*args, **kwargs)
    finally:
        mark("shader_module")
cube3d.create_shader_module = module
ctx = c.get_context()
mark("device")
st = cls(ctx, cls.default_format, None)
mark("pipeline")
st.resize((800, 600))
target = create_target(ctx, (800, 600), st.format)
mark("target")
enc = ctx.device.create_command_encoder()
st.record(enc, target, 0.0)
mark("record")
rb = _readback(ctx)
rb.record(enc, target)
mark("copy")
buf = enc.finish()
mark("finish")
ctx.queue.submit([buf])
mark("submit")
rb.read()
mark("first_pixel")
print(json.dumps(m))
"""


VARIANTS = ("as-is", "warm")  # warm: the probe also submits once on the device thread (not what the renderer does)


def main(runs: int, out: Path | None) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, WGPURENDER_VALIDATION="0", PYTHONPYCACHEPREFIX=str(Path(tmp) / "pyc"),
                   XDG_CACHE_HOME=str(Path(tmp) / "xdg"), MESA_SHADER_CACHE_DISABLE="true", __GL_SHADER_DISK_CACHE="0")
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env.setdefault("XDG_RUNTIME_DIR", "/tmp")
        samples: dict[str, list[dict]] = {v: [] for v in VARIANTS}
        for k in range(runs + 1):  # the first round warms the bytecode and wgpu.h's parse
            for variant in VARIANTS if k % 2 else VARIANTS[::-1]:
                proc = subprocess.run([sys.executable, "-c", CHILD, variant], capture_output=True, text=True, env=env,
                                      timeout=120)
                if proc.returncode:
                    raise SystemExit(proc.stderr[-2000:])
                if k:
                    samples[variant].append(json.loads(proc.stdout.strip().splitlines()[-1]))
    rows = []
    for variant, runs_ in samples.items():
        rows += sorted(({"variant": variant, "mark": key,
                         "median_ms": round(statistics.median(s[key] for s in runs_), 2),
                         "min_ms": round(min(s[key] for s in runs_), 2), "max_ms": round(max(s[key] for s in runs_), 2),
                         "runs": len(runs_)} for key in runs_[0]), key=lambda r: r["median_ms"])
    for r in rows:
        print(f"{r['variant']:6s} {r['mark']:24s} {r['median_ms']:9.1f} ms  [{r['min_ms']:.1f}..{r['max_ms']:.1f}]")
    if out:
        write_rows(out, rows)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 7, Path(sys.argv[2]) if len(sys.argv) > 2 else None)
