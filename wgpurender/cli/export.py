"""wgpurender export: a static page that renders a stage or a scene live with the browser's WebGPU."""

from __future__ import annotations

from wgpurender.cli._args import size_arg


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "export",
        help="write a static page that renders a stage or scene live in the browser (WebGPU)",
        description="Record what the wgpu path creates and draws for a stage or a scene file, and write a page "
        "(index.html, player.js, data.js) that replays it with the browser's WebGPU: open DIR/index.html from "
        "disk or any static server. window.wgpurender.capture() returns the frame at t = 0 (docs/backends.md).",
    )
    p.add_argument("target", metavar="STAGE|SCENE", help="a stage name or a scene .toml file")
    p.add_argument("-o", "--output", required=True, metavar="DIR",
                   help="folder for the page (made if missing, but its parent folder must exist; new, empty, or an "
                   "earlier output: only the files "
                   "wgpurender wrote there are replaced)")
    p.add_argument("--size", type=size_arg, default=(800, 600), metavar="WxH", help="canvas size (default 800x600)")
    p.add_argument("--force", action="store_true",
                   help="write into a non-empty folder that holds no earlier output, beside its files (none deleted)")
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.webpage import export

    done = export(args.target, args.output, args.size, force=args.force)
    kind = "animated" if done.animated else "still"
    print(f"wrote {done.page} ({done.size[0]}x{done.size[1]}, {kind}; {done.calls} recorded calls, "
          f"{done.page_bytes / 1e6:.2f} MB on disk)")
    return 0
