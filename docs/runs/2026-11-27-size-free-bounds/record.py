"""Render every target on each implementation, and each post scene with each effect dropped (native and browser),
at one size; save the PNGs under OUT/WxH/ (the measures are computed from them by measure.py).

    PYTHONPATH=.:tests python docs/runs/2026-11-27-size-free-bounds/record.py OUT WxH [--post-only | --targets A,B]

--targets draws only those targets and no dropped effects (the tutorial scenes, which need ../shared/anchors).
"""

import sys
import time
from pathlib import Path

from dropped_effects import without_post

from wgpurender import implementations as impls
from wgpurender.core.files.imageio import save_png, to_uint8
from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY
from wgpurender.core.scene import load_scene
from wgpurender.verify_matrix import render_all
from wgpurender.webpage import export
from wgpurender.webpage.chromium import Chromium
from wgpurender.wgpu_path.render import render_any

out, size = Path(sys.argv[1]), tuple(int(v) for v in sys.argv[2].split("x"))
root = out / sys.argv[2]
post = [n for n, p in impls.scene_files().items() if load_scene(p).post]
targets = post if "--post-only" in sys.argv else impls.all_targets()
if "--targets" in sys.argv:
    targets, post = sys.argv[sys.argv.index("--targets") + 1].split(","), []
t0 = time.time()
wanted = ["raw", "wgpu-vulkan", "wgpu-gl", "browser"]
images, skipped, who = render_all(wanted, targets, size, root / "work")
for impl, by in images.items():
    for name, img in by.items():
        (root / impl).mkdir(parents=True, exist_ok=True)
        save_png(root / impl / f"{name}.png", img)
(root / "who.txt").write_text("".join(f"{k}: {v}\n" for k, v in who.items()) +
                              "".join(f"skipped {k}: {v}\n" for k, v in skipped.items() if v))
print("matrix", round(time.time() - t0), flush=True)
files, pages = {}, {}
for sub in ("scenes", "pages", "drop-native", "drop-browser"):
    (root / sub).mkdir(parents=True, exist_ok=True)
for name in post:
    for k, step in enumerate(load_scene(impls.scene_files()[name]).post):
        stem = f"{name}-drop{k}-{step.effect}"
        path = without_post(impls.scene_files()[name], k, root / "scenes" / f"{stem}.toml")
        files[stem] = path
        img = to_uint8(render_any(str(path), size=size, backend="vulkan", anisotropy=REFERENCE_ANISOTROPY).pixels)
        save_png(root / "drop-native" / f"{stem}.png", img)
        pages[stem] = export(str(path), root / "pages" / stem, size).page
print("drops native", round(time.time() - t0), flush=True)
with Chromium(webgpu=True) as browser:
    for stem, page in pages.items():
        tab = browser.open(page)
        save_png(root / "drop-browser" / f"{stem}.png", tab.capture())
        tab.close()
print("drops browser", round(time.time() - t0), flush=True)
