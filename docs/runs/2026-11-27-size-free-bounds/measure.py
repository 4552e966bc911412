"""Every measure of the images record.py saved: each implementation against wgpu-vulkan, and each dropped-effect
render (wgpu-vulkan and browser) against wgpu-vulkan's full render, at each size recorded; writes measured.csv.

    PYTHONPATH=. python docs/runs/2026-11-27-size-free-bounds/measure.py IMAGES OUT.csv
"""

import csv
import sys
from pathlib import Path

import numpy as np

from wgpurender.core.files.imageio import load_png
from wgpurender.core.verdict.structure import gradient, luminance, structure
from wgpurender.core.verdict.tolerances import measure

FIELDS = ("size", "kind", "impl", "target", "effect", "max_abs", "changed_pixels", "pixels", "changed", "flip_mean",
          "radial", "detail", "detail_all")


def row(size, kind, impl, target, effect, ref, img):
    m, s = measure(ref, img), structure(ref, img)
    return {"size": size, "kind": kind, "impl": impl, "target": target, "effect": effect, "max_abs": m.max_abs,
            "changed_pixels": m.changed_pixels, "pixels": m.pixels, "changed": f"{m.changed:.6f}",
            "flip_mean": f"{m.flip_mean:.6f}", "radial": f"{s.radial:g}",
            "detail": f"{s.detail:.4f}", "detail_all": f"{detail_all(ref, img):.4f}"}


def detail_all(ref, img):
    """detail over every pixel, not only the reference's edges: the first version, kept to show why it changed."""
    return float(np.log2((gradient(luminance(img)).mean() + 1.0) / (gradient(luminance(ref)).mean() + 1.0)))


rows = []
for folder in sorted(Path(sys.argv[1]).iterdir(), key=lambda p: int(p.name.split("x")[0])):
    size = folder.name
    refs = {p.stem: load_png(p) for p in sorted((folder / "wgpu-vulkan").glob("*.png"))}
    for impl in ("raw", "wgpu-gl", "browser"):
        for target, ref in refs.items():
            if (folder / impl / f"{target}.png").is_file():
                rows.append(row(size, "baseline", impl, target, "", ref, load_png(folder / impl / f"{target}.png")))
    for side in ("wgpu-vulkan", "browser"):
        for p in sorted((folder / ("drop-native" if side == "wgpu-vulkan" else "drop-browser")).glob("*.png")):
            target, rest = p.stem.split("-drop")
            rows.append(row(size, "drop", side, target, rest.split("-", 1)[1], refs[target], load_png(p)))
    print(size, len(rows), flush=True)
with open(sys.argv[2], "w", newline="") as f:
    writer = csv.DictWriter(f, fieldnames=FIELDS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
