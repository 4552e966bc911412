"""Whose Python runs in the final scene's frame (issue 31.4, frame4's "fewer Python objects per frame"): the
Python function calls of one steady frame's record + submit (as ``bench perf``'s untimed rows draw it), counted
by cProfile and grouped by owner: ours (``wgpurender``), wgpu-py, cffi, the standard library (weakref, logging),
and builtins (C functions: ``isinstance``, ``setattr``, the native calls' proxies). A count, not a time: the
profiler's own cost would swamp a time.

    python benchmarks/frame_python_calls.py OUT.csv [W]x[H] [FRAMES]

One row per post path the plan allows here and owner: calls per frame (the mean over FRAMES frames).
"""

from __future__ import annotations

import cProfile
import pstats
import sys
from collections import Counter
from pathlib import Path

from probe_csv import write_rows

OWNERS = ("wgpurender", "wgpu-py", "cffi", "stdlib", "builtins")


def owner(filename: str) -> str:
    """Who wrote the function ``filename`` holds (cProfile names builtins ``~``)."""
    if filename == "~":
        return "builtins"
    parts = Path(filename).parts
    if "wgpurender" in parts:
        return "wgpurender"
    if "wgpu" in parts:
        return "wgpu-py"
    return "cffi" if "cffi" in parts else "stdlib"


def calls_per_frame(ctx, renderer, frames: int) -> Counter:
    """Python calls per frame of record + submit, by owner (the wait is not profiled)."""
    target = renderer.create_output()
    device, queue, record = ctx.device, ctx.queue, renderer.record
    profile = cProfile.Profile()
    for k in range(frames + 5):
        if k >= 5:
            profile.enable()
        encoder = device.create_command_encoder(label="calls")
        record(encoder, target, 0.0)
        queue.submit([encoder.finish()])
        profile.disable()
        ctx.wait_idle()
    counts: Counter = Counter()
    for (filename, _, _), (_, calls, *_) in pstats.Stats(profile).stats.items():
        counts[owner(filename)] += calls
    return Counter({k: v / frames for k, v in counts.items()})


def main() -> int:
    out = Path(sys.argv[1])
    size = tuple(int(v) for v in (sys.argv[2] if len(sys.argv) > 2 else "320x240").split("x"))
    frames = int(sys.argv[3]) if len(sys.argv) > 3 else 100

    from wgpurender.core.files.assets import resolve_scene
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene import load_renderer

    ctx = get_context()
    rows = []
    for post_path in ("fragment", "compute"):
        renderer = load_renderer(resolve_scene("final.toml"), ctx, size=size, knobs={"post_path": post_path})
        counts = calls_per_frame(ctx, renderer, frames)
        for who in OWNERS:
            rows.append({"post_path": post_path, "owner": who, "calls_per_frame": counts.get(who, 0.0)})
        rows.append({"post_path": post_path, "owner": "total", "calls_per_frame": sum(counts.values())})
        print(post_path, {k: round(v, 1) for k, v in counts.items()}, flush=True)
    write_rows(out, rows, digits=2)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
