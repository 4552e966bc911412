"""How much of the final scene's record + submit is our Python (issue 31.4's frametime pass): the frame as
``bench perf``'s untimed rows draw it (an encoder, ``renderer.record``, ``queue.submit``, then the blocking wait),
with every method of wgpu-py's encoder, pass encoders, queue, device and texture classes timed at class level
(outermost call only). What is left of the frame's wall time is the time outside wgpu-py: the renderer's own
Python (plus a little for the timing wrappers, the same in every tree).

Run it once per tree (PYTHONPATH picks the tree), in alternating rounds:

    python benchmarks/frame_python_probe.py OUT.csv TREE [SCENE] [W]x[H] [FRAMES] [same|new]

``new``: each frame draws into a new texture object of the same size, as a window's swapchain hands out (made
before the frame's clock starts, so only what the renderer does with it is timed), by the window's plan (no
storage output: the compute post path copies into it); ``same`` (the default): one
offscreen target, as ``bench perf`` draws. Appends one row per round (tree, scene, size, targets, frames, frame_us
and outside_us medians, the largest wgpu-py methods' mean microseconds per frame).
"""

from __future__ import annotations

import csv
import statistics
import sys
import time
from collections import Counter
from pathlib import Path

CLASSES = ("GPUCommandEncoder", "GPURenderPassEncoder", "GPUComputePassEncoder", "GPUQueue", "GPUDevice", "GPUTexture")


def wrap_wgpu_py(spent: Counter) -> None:
    """Time every public method of wgpu-py's classes the frame calls (outermost call only) into ``spent``."""
    from wgpu.backends.wgpu_native import _api

    depth = [0]
    for cls in (getattr(_api, name) for name in CLASSES):
        for name, method in list(vars(cls).items()):
            if name.startswith("_") or not callable(method):
                continue

            def timed(*args, _method=method, _key=f"{cls.__name__}.{name}", **kwargs):
                depth[0] += 1
                start = time.perf_counter()
                try:
                    return _method(*args, **kwargs)
                finally:
                    depth[0] -= 1
                    if depth[0] == 0:
                        spent[_key] += time.perf_counter() - start

            setattr(cls, name, timed)


def main() -> None:
    out, tree = Path(sys.argv[1]), sys.argv[2]
    scene = sys.argv[3] if len(sys.argv) > 3 else "final.toml"
    size = tuple(int(v) for v in (sys.argv[4] if len(sys.argv) > 4 else "320x240").split("x"))
    frames = int(sys.argv[5]) if len(sys.argv) > 5 else 300
    targets = sys.argv[6] if len(sys.argv) > 6 else "same"

    from wgpurender.bench.frames import settle_garbage
    from wgpurender.bench.scene import SceneRunner
    from wgpurender.core.files.assets import resolve_scene
    from wgpurender.wgpu_path.device.context import get_context

    ctx = get_context()
    runner = SceneRunner(ctx, resolve_scene(scene), size)
    record, target, device, queue = runner.renderer.record, runner.target, ctx.device, ctx.queue
    if targets == "new":  # the window's plan: a swapchain image is no storage texture (output_storage off)
        from wgpurender.wgpu_path.device.targets import TARGET_USAGE, create_target
        from wgpurender.wgpu_path.scene import load_renderer

        window = load_renderer(resolve_scene(scene), ctx, size=size, knobs={"output_storage": False})
        record = window.record

        def new_target():
            return create_target(ctx, size, window.plan.target_format, usage=TARGET_USAGE | window.target_usage)
    for _ in range(5):
        runner.frame(readback=True)
    spent: Counter = Counter()
    wrap_wgpu_py(spent)
    settle_garbage()
    totals, outside, per_method = [], [], Counter()
    for k in range(frames + 10):
        if targets == "new":
            target = new_target()  # the last one is released here, as a presented image is
        spent.clear()
        start = time.perf_counter()
        encoder = device.create_command_encoder(label="probe")
        record(encoder, target, 0.0)
        queue.submit([encoder.finish()])
        frame_us = (time.perf_counter() - start) * 1e6
        ctx.wait_idle()
        if k >= 10:
            totals.append(frame_us)
            outside.append(frame_us - sum(spent.values()) * 1e6)
            per_method.update({key: s * 1e6 / frames for key, s in spent.items()})
    largest = "; ".join(f"{key} {us:.1f}" for key, us in per_method.most_common(6))
    new = not out.exists()
    with out.open("a", newline="") as f:
        writer = csv.writer(f)
        if new:
            writer.writerow(("tree", "scene", "size", "targets", "frames", "frame_us", "outside_wgpu_py_us",
                             "wgpu_py_methods_us"))
        writer.writerow((tree, scene, f"{size[0]}x{size[1]}", targets, frames, f"{statistics.median(totals):.1f}",
                         f"{statistics.median(outside):.1f}", largest))
    print(tree, scene, size, targets, f"frame {statistics.median(totals):.1f} us, outside wgpu-py "
          f"{statistics.median(outside):.1f} us")


if __name__ == "__main__":
    main()
