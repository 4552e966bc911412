"""Regenerate assets/reference/<stage>.png with the raw-Vulkan path.

Run ``python -m wgpurender.raw_path.make_references`` (``make references``).

Every stage this path knows, at REFERENCE_SIZE, in its default format and MSAA; and
scene_<name>.png for each scene file of SCENE_REFERENCES, at SCENE_REFERENCE_SIZE.
Only this path ever writes these files (also through ``pytest --regenerate-references``);
tests/test_vulkan_ref*.py re-render them and compare within the calibrated bounds of
assets/reference/tolerances.toml. Float images (rgba16float) are stored as 8-bit sRGB PNGs
(imageio.to_uint8). A file whose pixels did not change is left untouched, and each run says, per
image, how many pixels changed and by how much at most.
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.assets import reference_dir, scene_dir

REFERENCE_SIZE = (256, 192)
REFERENCE_DIR = reference_dir()  # the checkout's assets/reference, or the wheel's copy
SCENE_DIR = scene_dir()
SCENE_REFERENCE_SIZE = (320, 240)
# reference name -> scene file in assets/scenes/ (only scenes the raw path can draw: per-pixel post effects)
SCENE_REFERENCES = {"scene_final_subpass": "final_subpass.toml", "scene_unlit": "unlit.toml",
                    "scene_gltf_features": "gltf_features.toml",
                    "scene_metal_rough_spheres": "metal_rough_spheres.toml"}


def reference_path(stage: str, directory: Path = REFERENCE_DIR) -> Path:
    return directory / f"{stage}.png"


@dataclass(frozen=True)
class Change:
    """What regenerating one reference did."""

    name: str
    path: Path
    pixels_changed: int  # pixels with any channel different from the old file (all of them when it was new)
    max_diff: int  # largest channel difference, 1/255
    new: bool

    def describe(self) -> str:
        if self.new:
            return f"{self.name}: new file {self.path}"
        if not self.pixels_changed:
            return f"{self.name}: unchanged"
        return f"{self.name}: {self.pixels_changed} pixels changed, max difference {self.max_diff}/255 ({self.path})"


def render_named_reference(name: str) -> np.ndarray:
    """The 8-bit image of reference ``name`` (a stage or a SCENE_REFERENCES key), by the raw path only; scenes
    with their own anisotropic filtering (REFERENCE_ANISOTROPY: :func:`main` says what that changes)."""
    from wgpurender.core.files.imageio import to_uint8
    from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY
    from wgpurender.raw_path import render_reference

    if name in SCENE_REFERENCES:
        return to_uint8(render_reference(str(SCENE_DIR / SCENE_REFERENCES[name]), size=SCENE_REFERENCE_SIZE,
                                         anisotropy=REFERENCE_ANISOTROPY))
    return to_uint8(render_reference(name, size=REFERENCE_SIZE))


def all_reference_names() -> list[str]:
    from wgpurender.raw_path import reference_stage_names

    return [*reference_stage_names(), *SCENE_REFERENCES]


def regenerate(directory: Path = REFERENCE_DIR, names: list[str] | None = None) -> list[Change]:
    """Re-render the references with the raw path; write those whose pixels changed (or are new)."""
    from wgpurender.core.files.imageio import load_png, save_png

    directory.mkdir(parents=True, exist_ok=True)
    changes = []
    for name in names or all_reference_names():
        pixels, path = render_named_reference(name), reference_path(name, directory)
        old = load_png(path) if path.is_file() else None
        if old is None or old.shape != pixels.shape:
            save_png(path, pixels)
            changes.append(Change(name, path, pixels.shape[0] * pixels.shape[1], 255, True))
            continue
        diff = np.abs(old.astype(np.int16) - pixels.astype(np.int16)).max(axis=-1)
        if diff.any():
            save_png(path, pixels)
        changes.append(Change(name, path, int(np.count_nonzero(diff)), int(diff.max()), False))
    return changes


def make_references(directory: Path = REFERENCE_DIR, stages: list[str] | None = None) -> list[Path]:
    """Regenerate and return the paths of the references (changed or not)."""
    return [c.path for c in regenerate(directory, stages)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m wgpurender.raw_path.make_references", description=__doc__)
    parser.add_argument("stages", nargs="*",
                        help="stages or scene references (scene_final_subpass, ...) to render (default: all)")
    parser.add_argument("--dir", type=Path, default=REFERENCE_DIR, help=f"output folder (default {REFERENCE_DIR})")
    args = parser.parse_args(argv)
    os.environ.setdefault("WGPURENDER_VALIDATION", "1")  # references come from a validation-clean path only
    try:
        for change in regenerate(args.dir, args.stages or None):
            print(change.describe())
        from wgpurender.core.plan.anisotropy import reference_difference
        from wgpurender.raw_path.device.context import get_vulkan

        differs = reference_difference(get_vulkan().adapter_facts().adapter_type)
        if differs:
            print(f"unlike `wgpurender render T`: {differs}")
    except UserError as err:
        print(f"make_references: error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
