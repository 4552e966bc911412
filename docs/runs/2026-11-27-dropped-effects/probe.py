import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

from wgpurender import implementations as impls
from wgpurender.core.files.imageio import to_uint8
from wgpurender.core.plan import resolve_plan
from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY
from wgpurender.core.scene import load_scene
from wgpurender.core.verdict.tolerances import implementation_tolerance, measure
from wgpurender.wgpu_path.device.context import get_context
from wgpurender.wgpu_path.scene import render_plan

size = tuple(int(v) for v in sys.argv[1].split("x"))
ctx = get_context("Vulkan")
names = [n for n, p in impls.scene_files().items() if load_scene(p).post]
t = time.time()
browser, skipped, who = impls.render_browser(names, size, Path("/tmp/truth_i6/pages") / sys.argv[1])
print("browser", time.time() - t, skipped, flush=True)
def mae(a, b):
    d = a[..., :3].astype(float) - b[..., :3].astype(float)
    h, w = d.shape[:2]
    gy, gx = 6, 8
    d = d[: h - h % gy, : w - w % gx].reshape(gy, h // gy, gx, w // gx, 3).mean(axis=(1, 3))
    return float(np.abs(d).max())
for name in names:
    scene = load_scene(impls.scene_files()[name])
    def draw(s):
        plan = resolve_plan(s, ctx.adapter_facts(), size=size, anisotropy=REFERENCE_ANISOTROPY)
        return to_uint8(render_plan(ctx, plan, frames=1).pixels)
    full = draw(scene)
    tol = implementation_tolerance("browser", name)
    b = browser.get(name)
    if b is not None:
        m = measure(full, b)
        print(f"{name}: browser vs native max {m.max_abs} changed {m.changed:.3f} flip {m.flip_mean:.4f} "
              f"mae {mae(full, b):.3f} exceeded {tol.exceeded(m)}", flush=True)
    for k, step in enumerate(scene.post):
        dropped = draw(dataclasses.replace(scene, post=tuple(s for j, s in enumerate(scene.post) if j != k)))
        m = measure(full, dropped)
        print(f"  drop {k} {step.effect if hasattr(step,'effect') else step}: max {m.max_abs} "
              f"changed {m.changed:.3f} flip {m.flip_mean:.4f} mae {mae(full, dropped):.3f} "
              f"exceeded {tol.exceeded(m)}", flush=True)
