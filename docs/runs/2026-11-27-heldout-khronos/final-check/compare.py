"""Compare two held-out runs' images (run.py's OUT/shots) view by view: for each view and each wgpurender path, the
largest channel difference and the share of pixels differing by more than 2/255 between the runs, and wgpu against
raw in the newer run. Usage: python compare.py OLD_OUT NEW_OUT > diff.csv"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np
from PIL import Image


def pixels(path: Path) -> np.ndarray | None:
    return np.asarray(Image.open(path).convert("RGB")).astype(int) if path.exists() else None


def main(old: Path, new: Path) -> None:
    out = csv.writer(sys.stdout)
    out.writerow(["view", "wgpu max diff", "wgpu share > 2/255", "raw max diff", "raw share > 2/255",
                  "wgpu vs raw max diff (new run)"])
    for view in sorted(p.name for p in (new / "shots").iterdir()):
        row = [view]
        for path in ("wgpu", "raw"):
            a, b = pixels(old / "shots" / view / f"{path}.png"), pixels(new / "shots" / view / f"{path}.png")
            if a is None or b is None:
                row += ["not drawn before" if b is not None else "not drawn now", ""]
                continue
            d = np.abs(a - b)
            row += [int(d.max()), f"{(d.max(axis=-1) > 2).mean():.4f}"]
        w, r = pixels(new / "shots" / view / "wgpu.png"), pixels(new / "shots" / view / "raw.png")
        row.append(int(np.abs(w - r).max()) if w is not None and r is not None else "")
        out.writerow(row)


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]))
