"""What each post effect costs: the final scene's frame time with its whole chain and with each effect removed.

    .venv/bin/python benchmarks/bench_effects.py [--frames N] [--warmup N] [--size WxH] [--scene PATH]
                                                 [--tutorial] [--markdown]

Per configuration: ``warmup`` untimed frames, then ``frames`` timed ones. A frame is record +
submit + wait for the GPU (the timestamp readback waits), no image readback. Reported: wall
time (median, p10, p90) and the GPU time of every pass from timestamp queries
(wgpurender.wgpu_path.device.timing.PassTimer; on lavapipe "GPU" time is CPU rasterisation time). An effect's
cost is the difference between the full chain and the chain without it, and its own pass time.

``--tutorial`` also times the Vulkan-tutorial scenes (chapters 28 and 30), to set beside the
C++ program's 47 ms / 75 ms (../shared/anchors/README.md).
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("XDG_RUNTIME_DIR", "/tmp")

from wgpurender.core.plan import resolve_plan  # noqa: E402
from wgpurender.core.scene import Scene, load_scene  # noqa: E402
from wgpurender.wgpu_path.device.context import get_context  # noqa: E402
from wgpurender.wgpu_path.device.frame_loop import run_frame  # noqa: E402
from wgpurender.wgpu_path.device.timing import PassTimer, Stats  # noqa: E402
from wgpurender.wgpu_path.scene import SceneRenderer  # noqa: E402


def time_scene(ctx, scene: Scene, size, frames: int, warmup: int) -> tuple[Stats, dict[str, Stats]]:
    """Wall-time stats of whole frames and GPU-time stats of each pass."""
    plan = resolve_plan(scene, None, size=size)
    renderer = SceneRenderer(ctx, scene, plan)
    target = renderer.create_output()
    timer = PassTimer(ctx)
    wall, gpu = [], {}
    record = functools.partial(renderer.record, timer=timer)
    for i in range(warmup + frames):
        # the timer read waits for the frame (or run_frame waits without timestamps)
        frame = run_frame(ctx, record, target, 0.0, label="bench", read_back=False, timer=timer)
        if i >= warmup:
            wall.append(frame.frame_ms)
            for label, ms in frame.gpu_ms.items():
                gpu.setdefault(label, []).append(ms)
    return Stats.of(wall), {label: Stats.of(v) for label, v in gpu.items()}


def configurations(scene: Scene) -> list[tuple[str, Scene]]:
    out = [("full chain: " + " -> ".join(s.effect for s in scene.post), scene)]
    for step in scene.post:
        rest = tuple(s for s in scene.post if s is not step)
        out.append((f"without {step.effect}", dataclasses.replace(scene, post=rest)))
    out.append(("no post chain (scene pass into the output)", dataclasses.replace(scene, post=())))
    out.append(("full chain, samplers at anisotropy 1", without_anisotropy(scene)))
    return out


def without_anisotropy(scene: Scene) -> Scene:
    """The scene with every material's sampler at anisotropy 1 (what anisotropic filtering costs)."""
    def plain(model):
        sampler = dataclasses.replace(model.material.sampler, anisotropy=1)
        return dataclasses.replace(model, material=dataclasses.replace(model.material, sampler=sampler))

    return dataclasses.replace(scene, models=tuple(plain(m) for m in scene.models))


def _fmt(s: Stats) -> str:
    return f"{s.median:.1f} ({s.p10:.1f}..{s.p90:.1f})"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scene", default=str(ROOT / "assets" / "scenes" / "final.toml"))
    p.add_argument("--frames", type=int, default=15)
    p.add_argument("--warmup", type=int, default=3)
    p.add_argument("--size", default=None, help="WxH (default: the scene's)")
    p.add_argument("--tutorial", action="store_true", help="also time the Vulkan-tutorial scenes")
    args = p.parse_args(argv)
    size = tuple(int(v) for v in args.size.split("x")) if args.size else None
    ctx = get_context()
    scene = load_scene(args.scene)
    w, h = size or scene.render.size
    print(f"# {Path(args.scene).name} {w}x{h}, {args.frames} frames after {args.warmup} warm-up; "
          f"adapter: {ctx.describe()}; {os.cpu_count()} CPU cores; {time.strftime('%Y-%m-%d')}")
    print("| configuration | wall ms median (p10..p90) | GPU ms per pass, median |")
    print("|---|---|---|")
    for name, variant in configurations(scene):
        wall, passes = time_scene(ctx, variant, size, args.frames, args.warmup)
        per_pass = ", ".join(f"{label} {s.median:.1f}" for label, s in passes.items()) or "no timestamps"
        print(f"| {name} | {_fmt(wall)} | {per_pass} |", flush=True)
    if args.tutorial:
        print()
        print("| Vulkan tutorial scene | wall ms median (p10..p90) | GPU ms per pass, median | C++ tutorial |")
        print("|---|---|---|---|")
        for chapter, cpp in (("28", 47), ("30", 75)):
            path = ROOT / "assets" / "scenes" / f"vulkan_tutorial_{chapter}.toml"
            wall, passes = time_scene(ctx, load_scene(path), None, args.frames, args.warmup)
            per_pass = ", ".join(f"{label} {s.median:.1f}" for label, s in passes.items())
            print(f"| chapter {chapter} | {_fmt(wall)} | {per_pass} | {cpp} ms |", flush=True)
    return 0


if __name__ == "__main__":
    np.seterr(all="ignore")
    sys.exit(main())
