"""Per-tile contrast of the three clearcoat rows of TextureTransformMultiTest (192 px frame)."""
import sys

import numpy as np
from PIL import Image

COLS = {"UV 0": 96, "UV 1": 110, "Sample": 124}  # left edge, 12 px wide
ROWS = {"Clearcoat": 121, "Clearcoat Rough": 135, "Clearcoat Normal": 149}
for path in sys.argv[1:]:
    lum = np.asarray(Image.open(path).convert("L")).astype(float)
    for row, y in ROWS.items():
        cells = [lum[y + 1:y + 11, x + 1:x + 11] for x in COLS.values()]
        contrast = [np.percentile(c, 95) - np.percentile(c, 5) for c in cells]
        spread = max(np.abs(cells[0] - c).mean() for c in cells[1:])
        print(f"{path},{row}," + ",".join(f"{c:.0f}" for c in contrast) + f",{spread:.1f}")
