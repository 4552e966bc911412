"""Device measurements for gpufix's second call: one JSON file."""
import json, os, sys, time
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests")
out = {}
def put(k, v):
    out[k] = v
    print(k, v, flush=True)
try:
    from wgpurender.raw_path.make_references import reference_path, render_named_reference
    from wgpurender.core.files.imageio import load_png
    from wgpurender.core.verdict.tolerances import measure, calibrate, tolerance
    for n in ("scene_metal_rough_spheres_ibl", "scene_metal_rough_spheres"):
        m = measure(load_png(reference_path(n)), render_named_reference(n))
        put(n, [m.summary(), calibrate([m], "gpu"), tolerance(n, "gpu").exceeded(m)])
except Exception as e:
    put("ref error", repr(e))
try:
    from wgpurender.core.course import ibl_maps
    from wgpurender.core.course.environment import sky
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.scene.ibl import make_maps as raw_maps
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene.ibl import make_maps as wgpu_maps
    env = sky()
    for s in (64, 256):
        r, g, c = raw_maps(get_vulkan(), env, s), wgpu_maps(get_context(), env, s), ibl_maps.make_arrays(env, s)
        put(f"maps {s}", {name: [bool(np.array_equal(getattr(r, name), getattr(g, name))),
                                 float(np.abs(getattr(r, name) - getattr(g, name)).max()),
                                 float(np.abs(getattr(r, name) - getattr(c, name)).max())] for name in ("irradiance", "prefiltered", "lut")})
        put(f"levels rel mean vs cpu {s}", [float(np.abs(g.prefiltered[k] - c.prefiltered[k]).mean() / c.prefiltered[k].mean()) for k in range(5)])
        put(f"level0 max rel {s}", float((np.abs(g.prefiltered[0] - c.prefiltered[0]) / np.maximum(np.abs(c.prefiltered[0]), 1e-6)).max()))
except Exception as e:
    import traceback; traceback.print_exc()
    put("maps error", repr(e))
try:
    from test_pbr import sphere_disc, GRID, SPHERES_BASE
    from shading_model import srgb_decode, course_constant
    from wgpurender.core.scene import load_scene
    from wgpurender.raw_path.scene import render_scene_reference
    scene = load_scene("assets/scenes/metal_rough_spheres.toml")
    raw = render_scene_reference(Path("assets/scenes/metal_rough_spheres.toml"))[..., :3]
    lin = srgb_decode(raw / 255.0)
    amb = np.asarray(course_constant("AMBIENT")) * np.asarray(SPHERES_BASE)
    rows = []
    for col in range(GRID):
        disc = sphere_disc(scene, GRID - 1, col)
        px = raw[disc].astype(float); d = lin[disc] - amb
        lo, hi = (srgb_decode(np.clip(px + k, 0, 255) / 255.0) - amb for k in (-1, 1))
        lit = (px < 250).all(-1) & (d[:, 0] > 0.05)
        old = lin[disc][(raw[disc] < 250).all(-1) & (lin[disc].sum(-1) > 0.05)]
        rows.append([col, int(lit.sum())] + [[round(float(np.median(d[lit, c] / d[lit, 0]) - SPHERES_BASE[c] / SPHERES_BASE[0]), 4),
                      round(float(np.median((hi[lit, c] / lo[lit, 0] - lo[lit, c] / hi[lit, 0]) / 2)), 4),
                      round(float(np.median(old[:, c] / old[:, 0]) - SPHERES_BASE[c] / SPHERES_BASE[0]), 4)] for c in (1, 2)])
    put("spheres [col, n, [new dev, bound, old dev] x (g, b)]", rows)
except Exception as e:
    import traceback; traceback.print_exc()
    put("spheres error", repr(e))
Path(os.environ["OUT"], "measure.json").write_text(json.dumps(out, indent=1, default=str))
