"""The final scene's native calls per steady frame, listed call by call (issue 31.4's passes pass), for each post
path as the plan allows it here, offscreen (a storage output where the compute path may write it) and by a window's
plan (no storage output: the compute path copies into it), each frame into the same target and into a new one.

    python benchmarks/frame_calls_list.py OUT.csv [W]x[H]

Counted by wrapping the device, queue and encoders (wgpurender/bench/calls.py); a texture's own calls (its view)
are not wrapped there, so they are counted here by wrapping the targets' create_view.
"""

from __future__ import annotations

import csv
import sys
from collections import Counter
from pathlib import Path


def _target(ctx, size, renderer, views: Counter):
    """A new output texture whose create_view calls are counted into ``views``."""
    from wgpurender.wgpu_path.device.targets import TARGET_USAGE, create_target

    texture = create_target(ctx, size, renderer.plan.target_format, usage=TARGET_USAGE | renderer.target_usage)
    real = texture.create_view

    def create_view(*args, **kwargs):
        views["texture.create_view"] += 1
        return real(*args, **kwargs)

    texture.create_view = create_view
    return texture


def main() -> None:
    out = Path(sys.argv[1])
    size = tuple(int(v) for v in (sys.argv[2] if len(sys.argv) > 2 else "320x240").split("x"))
    from wgpurender.bench.calls import count_frame, steady_calls
    from wgpurender.core.files.assets import resolve_scene
    from wgpurender.core.plan import resolve_plan
    from wgpurender.core.scene import load_scene
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene import SceneRenderer

    ctx = get_context()
    scene = load_scene(resolve_scene("final.toml"))
    rows = []
    for post_path in ("fragment", "compute"):
        for plan_of, storage in (("offscreen", True), ("window", False)):
            plan = resolve_plan(scene, ctx.adapter_facts(), size=size, post_path=post_path, output_storage=storage)
            renderer = SceneRenderer(ctx, plan.scene, plan)
            views: Counter = Counter()

            same = _target(ctx, size, renderer, views)
            steady = steady_calls(ctx, renderer.record, same)
            views.clear()
            new = count_frame(ctx, renderer.record, _target(ctx, size, renderer, views)) + views
            for targets, calls in (("same", steady), ("new", new)):
                for call, n in sorted(calls.items()):
                    rows.append((post_path, plan_of, targets, call, n))
                rows.append((post_path, plan_of, targets, "total", sum(calls.values())))
    with out.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(("post_path", "plan", "targets", "call", "count"))
        writer.writerows(rows)
    for row in rows:
        if row[3] == "total":
            print(*row)


if __name__ == "__main__":
    main()
