"""wgpurender info: the adapters this machine has and what the chosen one offers."""

from __future__ import annotations

from wgpurender.cli._args import add_backend_arg


def register(subparsers) -> None:
    p = subparsers.add_parser("info", help="show adapters, the chosen device, its features and limits, and where "
                              "the course's data (bundled scenes, reference images, the notebook) is")
    add_backend_arg(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.wgpu_path.device.context import _adapters, get_context

    print("adapters:")
    for a in _adapters(args.backend):
        info = a.info
        print(f"  {info['backend_type']:<8} {info['adapter_type']:<14} {info['device']} ({info['description']})")
    ctx = get_context(args.backend)
    print(f"chosen: {ctx.describe()}")
    print(f"optional features enabled: {', '.join(sorted(ctx.features)) or 'none'}")
    for name in (
        "max-texture-dimension-2d",
        "max-immediate-size",
        "min-uniform-buffer-offset-alignment",
        "max-bind-groups",
        "max-color-attachments",
    ):
        print(f"  {name}: {ctx.limit(name)}")
    _course_data()
    return 0


def _course_data() -> None:
    """Where the bundled course is (the checkout's folders, or the wheel's copies)."""
    from wgpurender.core.files.assets import assets_dir, notebook_path

    print(f"course data: {assets_dir()}")
    print(f"  bundled scenes (by name: wgpurender render final -o f.png): {', '.join(scene_labels())}")
    print(f"  notebook: {notebook_path()} (copy it anywhere and open it)")


NEEDS_FILES = " (needs the tutorial's files: see README)"


def scene_labels() -> list[str]:
    """The bundled scenes by name; one whose model or texture is absent here (the tutorial scenes read
    ../shared/anchors, never in a wheel) is marked, not listed as if it could render."""
    from wgpurender.core.files.assets import absent_files, bundled_scene_names, scene_dir

    return [name + (NEEDS_FILES if absent_files(scene_dir() / f"{name}.toml") else "")
            for name in bundled_scene_names()]
