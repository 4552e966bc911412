"""wgpurender new: start a scene of your own from a bundled one (its models and textures copied beside it)."""

from __future__ import annotations


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "new", help="copy a bundled scene into a new folder, with its models and textures, to edit",
        description="Copy a bundled scene (e.g. final) to NAME/NAME.toml with every model and texture it reads in "
        "NAME/models/ and NAME/textures/, its paths rewritten, so the copy renders from anywhere: "
        "'wgpurender render NAME/NAME.toml -o out.png' or 'wgpurender demo NAME/NAME.toml' (live reload).")
    p.add_argument("name", metavar="NAME", help="the new folder (must not exist)")
    p.add_argument("--from", dest="source", default="final", metavar="SCENE",
                   help="the scene to copy: a bundled scene's name or a .toml file (default final)")
    p.set_defaults(func=run)


def run(args) -> int:
    from pathlib import Path

    from wgpurender.core.errors import UserError
    from wgpurender.core.files.assets import bundled_scene_names, resolve_scene
    from wgpurender.core.scene.copy import copy_scene

    source = resolve_scene(args.source)
    if not source.is_file():
        raise UserError(f"--from {args.source!r}: no such scene; bundled scenes are "
                        f"{', '.join(bundled_scene_names())}, or give a scene file (.toml)")
    scene = copy_scene(source, Path(args.name))
    print(f"wrote {scene} (from {source.name}); render it: wgpurender render {scene} -o {Path(args.name).name}.png")
    return 0
