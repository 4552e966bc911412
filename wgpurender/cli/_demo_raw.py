"""``wgpurender demo --raw``: the demo's flags, run by the raw-Vulkan window (wgpurender/raw_path/window.py).

The same orbit camera, keys, FPS title and ``--benchmark`` CSV as the wgpu window: both take them from
the core (core/controls.py, core/frame_times.py).
"""

from __future__ import annotations


def run_raw(args) -> int:
    from pathlib import Path

    from wgpurender.core.controls import parse_script
    from wgpurender.core.errors import UserError
    from wgpurender.core.frame_times import BenchmarkSpec
    from wgpurender.core.imageio import check_writable, save_png
    from wgpurender.raw_path.window import run_raw_window

    if args.frames is not None and args.frames < 1:
        raise UserError("--frames must be at least 1")
    if args.screenshot:
        check_writable(args.screenshot)
    if args.backend:
        raise UserError("--backend picks a wgpu backend: the raw path is Vulkan only, leave it out with --raw")
    benchmark = None
    if args.benchmark:
        benchmark = BenchmarkSpec(args.benchmark_warmup, args.benchmark_runtime, Path(args.benchmark_result_file))
        check_writable(benchmark.csv_path)
    script = parse_script(args.test_input)
    result = run_raw_window(args.target, size=args.size, present_mode=args.present_mode, frames=args.frames,
                            screenshot=bool(args.screenshot), msaa=args.msaa, fixed_time=args.time,
                            benchmark=benchmark, script=script, anisotropy=args.anisotropy)
    print(f"surface offers: {result.offered}")
    print(f"swapchain: {result.swapchain_format}, present mode {result.present_mode}, "
          f"re-created {result.recreated} time(s)")
    for event in result.events:
        print(f"  {event}")
    print(f"frames: {result.frames}, mean frame time {result.mean_frame_ms:.2f} ms")
    if result.benchmark is not None:
        print(result.benchmark.summary())
        print(f"wrote {result.benchmark.write_csv()}")
    if args.screenshot and result.last_frame is not None:
        print(f"wrote {save_png(args.screenshot, result.last_frame)}")
    return 0
