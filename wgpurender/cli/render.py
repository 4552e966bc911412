"""wgpurender render: a stage (or a scene file) headless to a PNG."""

from __future__ import annotations

from wgpurender.cli._args import add_anisotropy_arg, add_camera_arg, add_render_args


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "render",
        help="render a stage or a scene headless to a PNG",
        description="Render a course stage (see 'wgpurender stages') or a scene file (.toml) offscreen "
        "and write a PNG.",
    )
    p.add_argument("target", metavar="STAGE|SCENE", help="a stage name or a scene .toml file")
    p.add_argument("-o", "--output", metavar="IMAGE",
                   help="output image (written atomically), .png; .jpg, .bmp, .tif, .webp by suffix; required "
                   "unless --explain")
    p.add_argument("--explain", action="store_true",
                   help="print the scene's render plan (passes, attachments, pipelines and why); with -o also render")
    add_anisotropy_arg(p)
    add_camera_arg(p)
    add_render_args(p)
    p.set_defaults(func=run)


def run(args) -> int:
    """The API's render and plan (wgpurender/api.py), so the CLI's image and plan are the API's."""
    from wgpurender import api
    from wgpurender.core.course.formats import is_scene_file
    from wgpurender.core.errors import UserError
    from wgpurender.core.files.imageio import check_writable, image_format

    scene = is_scene_file(args.target)
    if args.explain and not scene:
        raise UserError(f"--explain needs a scene file (.toml), got stage {args.target!r}")
    if not args.output and not args.explain:
        raise UserError("render needs -o PNG (the output path), or --explain to print a scene's plan")
    if args.output:
        image_format(args.output)  # refuse an unknown suffix before rendering
        check_writable(args.output)
    flags = {"size": args.size, "msaa": args.msaa, "format": args.format, "backend": args.backend,
             "anisotropy": args.anisotropy, "camera": args.camera}  # the API refuses either beside a stage
    if args.explain:
        print(api.explain(args.target, t=args.time, **flags), end="")
        if not args.output:
            return 0
    image = api.render(args.target, t=args.time, **flags)
    path = image.save(args.output)
    print(f"wrote {path} ({image.size[0]}x{image.size[1]})")
    print(f"adapter: {image.adapter}")
    print(f"frame time: {image.timings['frame_ms']:.2f} ms")
    return 0
