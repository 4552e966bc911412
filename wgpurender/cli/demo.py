"""wgpurender demo: a stage or a scene in a window, with an orbit camera, live reload and a benchmark mode."""

from __future__ import annotations

import argparse

from wgpurender.cli._args import add_anisotropy_arg, size_arg, time_arg

BENCHMARK_DEFAULTS = {"benchmark_warmup": 2.0, "benchmark_runtime": 10.0, "benchmark_result_file": "benchmark.csv"}
CONTROLS = ("left drag orbits, right/middle drag pans, scroll zooms; arrows/WASD orbit, +/- (Q/E) zoom, "
            "R or Home resets the camera, F1 shows/hides the overlay, P pauses the animation, Esc quits")


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of seconds, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a number of seconds >= 0, got {text!r}")
    return value


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "demo",
        help="show a stage or a scene in a window (orbit camera, live reload, --benchmark)",
        description="Open a GLFW window and draw a stage (see 'wgpurender stages') or a scene file (.toml). "
        f"Scenes and the 3d stage have an orbit camera: {CONTROLS}. The title shows FPS and frame time. "
        "Editing a WGSL file the pipeline uses ($WGPURENDER_SHADERS or shaders_wgsl/) or the scene file "
        "rebuilds it; a broken file prints file:line once and the last good frame stays on screen. "
        "See also 'wgpurender report -o DIR', the course on one page.",
    )
    p.add_argument("target", metavar="STAGE|SCENE", help="a stage name or a scene .toml file")
    p.add_argument("--size", type=size_arg, default=None, metavar="WxH",
                   help="window size (default: a scene's [render] size, as render's; 800x600 for a stage)")
    p.add_argument("--msaa", type=int, default=None, metavar="N", help="MSAA sample count, 1 or 4")
    p.add_argument(
        "--present-mode",
        default="fifo",
        choices=("fifo", "immediate", "mailbox"),
        metavar="fifo|immediate",
        help="fifo: vsync, never tears (default); immediate: no vsync (wgpu falls back to mailbox, then fifo, "
        "when the surface lacks it). mailbox only with --raw, where the surface offers it: wgpu-py 0.32 cannot "
        "ask for it alone",
    )
    p.add_argument("--frames", type=int, default=None, metavar="N", help="exit after N frames")
    p.add_argument("--time", type=time_arg, default=None, metavar="T",
                   help="freeze the animation at T seconds: a stage's, or a scene's glTF animations (which otherwise "
                   "play from the clock, looping; P pauses)")
    p.add_argument("--screenshot", default=None, metavar="PNG", help="save the last presented frame to PNG")
    p.add_argument("--backend", default=None,
                   help="graphics backend: vulkan (default), opengl or auto; also $WGPURENDER_BACKEND")
    add_anisotropy_arg(p)
    p.add_argument("--raw", action="store_true",
                   help="draw with the raw-Vulkan path: its own surface, swapchain, semaphores, fences and frames "
                   "in flight (wgpurender/raw_path/window/__init__.py); stages as 'wgpurender reference' has them; "
                   "--anisotropy, --validation and --benchmark work there too, --backend is refused")
    p.add_argument("--validation", action="store_true",
                   help="turn on the Vulkan validation layer (as $WGPURENDER_VALIDATION=1) and count its messages")
    bench = p.add_argument_group("benchmark (like Sascha Willems' Vulkan examples)")
    bench.add_argument("--benchmark", action="store_true",
                       help="warm up, run for a fixed time, write per-frame times to CSV, then exit")
    bench.add_argument("--benchmark-warmup", type=_positive, default=BENCHMARK_DEFAULTS["benchmark_warmup"],
                       metavar="S", help="seconds drawn before timing starts (default 2)")
    bench.add_argument("--benchmark-runtime", type=_positive, default=BENCHMARK_DEFAULTS["benchmark_runtime"],
                       metavar="S", help="seconds of timed frames (default 10)")
    bench.add_argument("--benchmark-result-file", default=BENCHMARK_DEFAULTS["benchmark_result_file"], metavar="CSV",
                       help="where the per-frame times go: frame,frame_ms (default benchmark.csv; --raw too)")
    p.add_argument("--no-overlay", action="store_true",
                   help="hide the settings overlay (the plan's knobs turned live, frame time, GPU time per pass, plan "
                   "memory; needs imgui-bundle: pip install 'wgpurender[overlay]'); --benchmark hides it too")
    p.add_argument("--record", default=None, metavar="OUT",
                   help="write every presented frame: OUT.mp4 (H.264, needs imageio-ffmpeg) or a folder of PNG frames "
                   "(--raw too)")
    p.add_argument("--record-fps", type=float, default=None, metavar="N",
                   help="the video's frame rate (default 30; each presented frame is one video frame)")
    p.add_argument("--force", action="store_true",
                   help="--record into a non-empty folder that holds no earlier recording, beside its files")
    p.add_argument("--test-input", default="", help=argparse.SUPPRESS)  # synthetic test input (core/view/controls.py)
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.core.course.formats import is_scene_file
    from wgpurender.core.errors import UserError
    from wgpurender.core.plan.anisotropy import check_applies

    if args.frames is not None and args.frames < 1:
        raise UserError("--frames must be at least 1")
    benchmark = _benchmark(args)
    size = _window_size(args.target, args.size)
    check_applies(args.target, is_scene_file(args.target), args.anisotropy)
    if is_scene_file(args.target):
        from wgpurender.api import check_static

        check_static(args.target, args.time)
    video = _video(args)
    try:
        if args.raw:
            from wgpurender.cli._demo_raw import run_raw

            code = run_raw(args, benchmark, size, video)
        else:
            code = _run_wgpu(args, benchmark, size, video)
    except BaseException:
        if video is not None:
            video.abort()  # a failed run publishes no partial video
        raise
    if video is not None:
        video.close()
        print(f"wrote {video.path} ({video.count} frames)")
    return code


def _video(args):
    """The --record writer (its output checked now, before a window opens), or None."""
    from wgpurender.core.errors import UserError
    from wgpurender.core.files.video import FrameWriter, check_output

    if args.record is None:
        if args.record_fps is not None:
            raise UserError("--record-fps sets the frame rate of --record: add --record OUT, or leave it out")
        if args.force:
            raise UserError("--force applies to --record: add --record OUT, or leave it out")
        return None
    check_output(args.record)
    return FrameWriter(args.record, 30.0 if args.record_fps is None else args.record_fps, force=args.force)


def _run_wgpu(args, benchmark, size, video) -> int:
    import os

    from wgpurender.wgpu_path.device.context import VALIDATION_ENV

    if args.validation:
        os.environ[VALIDATION_ENV] = "1"  # read when the first adapter is made, just below
    if args.validation:
        from wgpurender.wgpu_path.device.validation import collect_validation_messages

        counter = collect_validation_messages()
    else:
        counter = None
    result, ctx = _show(args, benchmark, size, video)
    print(f"adapter: {ctx.describe()}")
    print(f"frames: {result.frames}, mean frame time {result.mean_frame_ms:.2f} ms")
    if result.benchmark is not None:
        print(result.benchmark.summary())
        print(f"wrote {result.benchmark.write_csv()}")
    if args.screenshot and result.last_frame is not None:
        from wgpurender.core.files.imageio import save_image

        print(f"wrote {save_image(args.screenshot, result.last_frame)}")
    if counter is not None:
        print(f"validation messages: {len(counter.messages)}")
    return 0


def _benchmark(args):
    """The --benchmark spec (its CSV checked writable now, before a window opens), or None without it; the
    --benchmark-* settings without --benchmark are refused rather than ignored."""
    from pathlib import Path

    from wgpurender.core.errors import UserError
    from wgpurender.core.files.imageio import check_writable
    from wgpurender.core.view.frame_times import BenchmarkSpec

    if not args.benchmark:
        given = [f"--{name.replace('_', '-')}" for name, default in BENCHMARK_DEFAULTS.items()
                 if getattr(args, name) != default]
        if given:
            raise UserError(f"{given[0]} sets up the benchmark mode: add --benchmark, or leave it out")
        return None
    spec = BenchmarkSpec(args.benchmark_warmup, args.benchmark_runtime, Path(args.benchmark_result_file))
    check_writable(spec.csv_path)
    return spec


def _window_size(target: str, asked: tuple[int, int] | None) -> tuple[int, int]:
    """--size, else a scene's [render] size (the size ``render`` draws it at), else 800x600 for a stage."""
    from wgpurender.core.course.formats import is_scene_file

    if asked is not None:
        return asked
    if is_scene_file(target):
        from wgpurender.core.scene import load_scene

        return tuple(load_scene(target).render.size)
    return (800, 600)


def _show(args, benchmark, size, video):
    from wgpurender.core.files.imageio import check_writable, image_format
    from wgpurender.core.view.controls import parse_script
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.window import run_window
    from wgpurender.wgpu_path.window.view import DemoView

    if args.screenshot:
        image_format(args.screenshot)  # the suffix picks the format; refuse an unknown one before a window
        check_writable(args.screenshot)
    script = parse_script(args.test_input)
    ctx = get_context(args.backend)
    view = DemoView(ctx, args.target, args.msaa, anisotropy=args.anisotropy)
    view.check()  # fail on a bad stage name, scene or option before a window opens
    result = run_window(ctx, view, title=f"wgpurender: {args.target}", size=size, frames=args.frames,
                        present_mode=args.present_mode, fixed_time=args.time, screenshot=bool(args.screenshot),
                        benchmark=benchmark, script=script, video=video, overlay=not (args.no_overlay or benchmark))
    return result, ctx
