"""wgpurender demo: a stage or a scene in a window."""

from __future__ import annotations

from ._args import finite_float, size_arg


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "demo",
        help="show a stage or a scene in a window",
        description="Open a GLFW window and draw a stage (see 'wgpurender stages') or a scene file (.toml). "
        "Esc or the close button ends it.",
    )
    p.add_argument("target", metavar="STAGE|SCENE", help="a stage name or a scene .toml file")
    p.add_argument("--size", type=size_arg, default=(800, 600), metavar="WxH", help="window size (default 800x600)")
    p.add_argument("--msaa", type=int, default=None, metavar="N", help="MSAA sample count, 1 or 4")
    p.add_argument(
        "--present-mode",
        default="fifo",
        choices=("fifo", "mailbox", "immediate"),
        help="swapchain present mode (default fifo, always available)",
    )
    p.add_argument("--frames", type=int, default=None, metavar="N", help="exit after N frames")
    p.add_argument("--time", type=finite_float, default=None, metavar="T", help="freeze the animation at T seconds")
    p.add_argument("--screenshot", default=None, metavar="PNG", help="save the last presented frame to PNG")
    p.add_argument("--backend", default=None, help="graphics backend (default Vulkan; also $WGPURENDER_BACKEND)")
    p.add_argument("--anisotropy", choices=("auto", "scene"), default="auto",
                   help="auto (default): the scene's anisotropic filtering on a GPU, 1 on a CPU driver such as "
                   "lavapipe (seconds per frame there otherwise; --explain says why); scene: always the scene's")
    p.add_argument("--raw", action="store_true",
                   help="draw with the raw-Vulkan path: its own surface, swapchain, semaphores, fences and frames "
                   "in flight (wgpurender/vulkan_ref/window.py); stages as 'wgpurender reference' has them")
    p.set_defaults(func=run)


def run(args) -> int:
    if args.raw:
        from ._demo_raw import run_raw

        return run_raw(args)
    from ..course.formats import is_scene_file
    from ..errors import UserError
    from ..gpu import get_context
    from ..imageio import check_writable, save_png
    from ..window import run_window

    if args.frames is not None and args.frames < 1:
        raise UserError("--frames must be at least 1")
    if args.screenshot:
        check_writable(args.screenshot)
    ctx = get_context(args.backend)
    make = _drawable_factory(ctx, args)
    if not is_scene_file(args.target):  # a scene file was loaded and planned by its factory: no second renderer
        make("rgba8unorm-srgb")  # fail on a bad stage name or option before a window opens
    result = run_window(
        ctx,
        make,
        title=f"wgpurender: {args.target}",
        size=args.size,
        frames=args.frames,
        present_mode=args.present_mode,
        fixed_time=args.time,
        screenshot=bool(args.screenshot),
    )
    print(f"adapter: {ctx.describe()}")
    print(f"frames: {result.frames}, mean frame time {result.mean_frame_ms:.2f} ms")
    if args.screenshot and result.last_frame is not None:
        print(f"wrote {save_png(args.screenshot, result.last_frame)}")
    return 0


def _drawable_factory(ctx, args):
    from ..course.formats import is_scene_file

    if is_scene_file(args.target):
        from ..scene_render import scene_drawable_factory

        return scene_drawable_factory(args.target, ctx, msaa=args.msaa, anisotropy=args.anisotropy)
    from ..stages import get_stage

    cls = get_stage(args.target)
    return lambda fmt: cls(ctx, fmt, args.msaa)
