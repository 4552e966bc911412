"""wgpurender report: the course on one static page (both paths' images, differences, timings, code)."""

from __future__ import annotations

from wgpurender.cli._args import add_anisotropy_arg, add_backend_arg, size_arg


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "report",
        help="write the visual course report: a static HTML site with both paths' images per course step",
        description="Render every course step (stages, then scene files) on the wgpu path and the raw-Vulkan path, "
        "and write DIR/index.html with PNG files beside it: per step its description, both images side by side "
        "(click: rendered at twice the size), the difference heatmap and its scale, PSNR and FLIP, GPU and frame "
        "time on both paths, what changed in the code from the previous step, "
        "the code that makes the step on both paths side by side (highlighted, linked to the whole file), the "
        "Vulkan -> wgpu concept rows, and for scenes the render plan; then the accuracy Pareto plot and the hard "
        "cases, both measured in this run (a quick variant). Opens from disk in any browser (no network). Needs "
        "glslc for the raw path.",
    )
    p.add_argument("-o", "--output", required=True, metavar="DIR",
                   help="folder for the site (new, empty, or an earlier report: only the files the report wrote are "
                   "replaced, the user's own files are kept)")
    p.add_argument("--size", type=size_arg, default=None, metavar="WxH",
                   help="every step's image size (default 640x480, for a projector; a click opens twice that)")
    p.add_argument("--force", action="store_true",
                   help="write into a non-empty folder that holds no earlier output, beside its files (none deleted)")
    add_backend_arg(p)
    add_anisotropy_arg(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.report import build_report
    from wgpurender.wgpu_path.device.context import get_context

    index = build_report(args.output, size=args.size, ctx=get_context(args.backend), anisotropy=args.anisotropy,
                         force=args.force)
    print(f"wrote {index}")
    return 0
