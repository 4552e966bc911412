"""wgpurender reference: a stage rendered by the raw-Vulkan reference path to a PNG."""

from __future__ import annotations

from wgpurender.cli._args import add_anisotropy_arg, add_camera_arg, format_arg, msaa_arg, size_arg, time_arg


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "reference",
        help="render a stage or a scene file with the raw-Vulkan reference path (GLSL + vulkan binding) to a PNG",
        description="Render a course stage or a scene file (SCENE.toml: the post chain in a second subpass, "
        "per-pixel effects only) with raw Vulkan calls (no wgpu), headless, and write a PNG. "
        "Needs glslc (apt install glslc); $WGPURENDER_VALIDATION=1 turns on the validation layer.",
    )
    p.add_argument("stage", metavar="STAGE",
                   help="a stage name, e.g. clear-pass, triangle, msaa, msaa-post, or a scene file SCENE.toml")
    p.add_argument("-o", "--output", required=True, metavar="IMAGE",
                   help="output image (written atomically): .png, or .jpg, .bmp, .tif, .webp by suffix")
    p.add_argument("--size", type=size_arg, default=None, metavar="WxH",
                   help="image size (default 800x600; a scene file's [render] size)")
    p.add_argument("--msaa", type=msaa_arg, default=None, metavar="N",
                   help="MSAA sample count, 1 or 4 (default: the stage's or scene's)")
    p.add_argument("--format", type=format_arg, default=None, metavar="F",
                   help="colour format: rgba8unorm, rgba8unorm-srgb (default) or rgba16float (default for a scene: its "
                   "output_format)")
    p.add_argument("--time", type=time_arg, default=0.0, metavar="T",
                   help="a stage's animation time in seconds (default 0); for a scene, the time its glTF models' "
                   "animations are posed at (a static scene: only 0)")
    add_anisotropy_arg(p)
    add_camera_arg(p)
    p.set_defaults(func=run)


def run(args) -> int:
    """The API's reference (wgpurender/api.py): a scene's plan resolved for the raw device by the one function."""
    from wgpurender import api
    from wgpurender.core.files.imageio import check_writable, image_format

    image_format(args.output)  # refuse an unknown suffix before rendering
    check_writable(args.output)
    image = api.reference(args.stage, size=args.size, msaa=args.msaa, format=args.format, t=args.time,
                          anisotropy=args.anisotropy, camera=args.camera)
    path = image.save(args.output)
    print(f"wrote {path} ({image.size[0]}x{image.size[1]})")
    print(f"device: {image.adapter}")
    return 0
