"""Regenerate assets/reference/<stage>.png with the raw-Vulkan path.

Run ``python -m wgpurender.vulkan_ref.make_references`` (``make references``).

Every stage this path knows, at REFERENCE_SIZE, in its default format and MSAA; and
scene_<name>.png for each scene file of SCENE_REFERENCES, at SCENE_REFERENCE_SIZE.
Only this path ever writes these files; tests/test_vulkan_ref.py re-renders them
and compares, so a change in either the images or the path cannot go unnoticed.
Float images (rgba16float) are stored as 8-bit sRGB PNGs (imageio.to_uint8).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from ..errors import UserError

REFERENCE_SIZE = (256, 192)
REFERENCE_DIR = Path(__file__).resolve().parent.parent.parent / "assets" / "reference"
SCENE_DIR = REFERENCE_DIR.parent / "scenes"
SCENE_REFERENCE_SIZE = (320, 240)
# reference name -> scene file in assets/scenes/ (only scenes the raw path can draw: per-pixel post effects)
SCENE_REFERENCES = {"scene_final_subpass": "final_subpass.toml", "scene_unlit": "unlit.toml"}


def reference_path(stage: str, directory: Path = REFERENCE_DIR) -> Path:
    return directory / f"{stage}.png"


def make_references(directory: Path = REFERENCE_DIR, stages: list[str] | None = None) -> list[Path]:
    from ..imageio import save_png
    from . import reference_stage_names, render_reference

    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for stage in stages or [*reference_stage_names(), *SCENE_REFERENCES]:
        if stage in SCENE_REFERENCES:
            pixels = render_reference(str(SCENE_DIR / SCENE_REFERENCES[stage]), size=SCENE_REFERENCE_SIZE)
        else:
            pixels = render_reference(stage, size=REFERENCE_SIZE)
        written.append(save_png(reference_path(stage, directory), pixels))
    return written


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m wgpurender.vulkan_ref.make_references", description=__doc__)
    parser.add_argument("stages", nargs="*",
                        help="stages or scene references (scene_final_subpass, ...) to render (default: all)")
    parser.add_argument("--dir", type=Path, default=REFERENCE_DIR, help=f"output folder (default {REFERENCE_DIR})")
    args = parser.parse_args(argv)
    os.environ.setdefault("WGPURENDER_VALIDATION", "1")  # references come from a validation-clean path only
    try:
        for path in make_references(args.dir, args.stages or None):
            print(f"wrote {path}")
    except UserError as err:
        print(f"make_references: error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
