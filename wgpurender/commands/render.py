"""wgpurender render: a stage (or a scene file) headless to a PNG."""

from __future__ import annotations

from ._args import add_render_args


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "render",
        help="render a stage or a scene headless to a PNG",
        description="Render a course stage (see 'wgpurender stages') or a scene file (.toml) offscreen "
        "and write a PNG.",
    )
    p.add_argument("target", metavar="STAGE|SCENE", help="a stage name or a scene .toml file")
    p.add_argument("-o", "--output", required=True, metavar="PNG", help="output PNG path (written atomically)")
    add_render_args(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..imageio import check_writable, save_png
    from ..render import render_any

    check_writable(args.output)
    result = render_any(args.target, size=args.size, fmt=args.format, msaa=args.msaa, t=args.time, backend=args.backend)
    path = save_png(args.output, result.pixels)
    print(f"wrote {path} ({result.pixels.shape[1]}x{result.pixels.shape[0]})")
    print(f"adapter: {result.adapter}")
    print(f"frame time: {result.frame_ms:.2f} ms")
    return 0
