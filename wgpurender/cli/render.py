"""wgpurender render: a stage (or a scene file) headless to a PNG."""

from __future__ import annotations

from wgpurender.cli._args import add_render_args


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
    p.add_argument("--anisotropy", choices=("auto", "scene"), default="auto",
                   help="auto (default): the scene's anisotropic filtering on a GPU, 1 on a CPU driver such as "
                   "lavapipe (seconds per frame there otherwise; --explain says why); scene: always the scene's")
    add_render_args(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.core.course.formats import is_scene_file
    from wgpurender.core.errors import UserError
    from wgpurender.core.imageio import check_writable, image_format, save_image
    from wgpurender.wgpu_path.render import render_any

    if args.explain:
        if not is_scene_file(args.target):
            raise UserError(f"--explain needs a scene file (.toml), got stage {args.target!r}")
        from wgpurender.core.plan import explain_scene

        adapter = _adapter(args.backend)
        print(explain_scene(args.target, adapter=adapter, size=args.size, output_format=args.format, msaa=args.msaa,
                            anisotropy=args.anisotropy, adapter_type=adapter.adapter_type if adapter else None),
              end="")
        if not args.output:
            return 0
    if not args.output:
        raise UserError("render needs -o PNG (the output path), or --explain to print a scene's plan")
    image_format(args.output)  # refuse an unknown suffix before rendering
    check_writable(args.output)
    result = render_any(args.target, size=args.size, fmt=args.format, msaa=args.msaa, t=args.time, backend=args.backend,
                        anisotropy=args.anisotropy)
    path = save_image(args.output, result.pixels)
    print(f"wrote {path} ({result.pixels.shape[1]}x{result.pixels.shape[0]})")
    print(f"adapter: {result.adapter}")
    print(f"frame time: {result.frame_ms:.2f} ms")
    return 0


def _adapter(backend):
    """The adapter the renderer would use, for the plan's "auto" knobs; None (and a plan that says so) without one."""
    from wgpurender.core.errors import UserError
    from wgpurender.wgpu_path.gpu import get_context
    from wgpurender.wgpu_path.scene_render.frame import adapter_facts

    try:
        return adapter_facts(get_context(backend))
    except UserError:
        return None
