"""Device dump for gpufix: images and maps for local analysis."""
import os, sys, time, json
from pathlib import Path
import numpy as np
out = Path(os.environ["OUT"])
t0 = time.time()
def log(*a):
    print(f"[{time.time()-t0:6.1f}s]", *a, flush=True)
try:
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene import render_scene_file
    for name in ("metal_rough_spheres", "metal_rough_spheres_ibl"):
        p = Path("assets/scenes") / f"{name}.toml"
        raw = render_scene_reference(p)
        np.save(out / f"{name}_raw.npy", raw)
        log(name, raw.shape)
except Exception as e:
    log("spheres failed", repr(e))
try:
    from wgpurender.core.course.environment import sky
    from wgpurender.wgpu_path.scene.ibl import make_maps
    env = sky()
    for s in (16, 64, 256):
        m = make_maps(get_context(), env, s)
        np.savez(out / f"ibl_gpu_{s}.npz", irradiance=m.irradiance, prefiltered=m.prefiltered, lut=m.lut)
    log("ibl done")
except Exception as e:
    log("ibl failed", repr(e))
try:
    from wgpurender.exercises import check, source
    from wgpurender.exercises.catalogue import exercise
    from wgpurender.core.verdict.tolerances import measure
    res = {}
    for path in ("wgpu", "raw"):
        ex = exercise("5", path)
        imgs = {"solution": check.render_variant(source.solution_source(ex), ex)}
        for m in ex.mistakes:
            imgs[m.key] = check.mistake_images(ex, m.key)
        imgs["again_mips"] = check.render_variant(source.mistake_source(ex, next(m for m in ex.mistakes if m.key == "mips")), ex)
        np.savez(out / f"ex5_{path}.npz", **{f"{k}_{i}": v for k, vs in imgs.items() for i, v in enumerate(vs)})
        for a in imgs:
            for b in imgs:
                if a < b:
                    res[f"{path}:{a}-{b}"] = [measure(x, y).summary() for x, y in zip(imgs[a], imgs[b])]
        d = check.diagnose(imgs["mips"], ex, check.step_tolerance(ex))
        res[f"{path}:diagnose-mips"] = d.text()
    (out / "ex5.json").write_text(json.dumps(res, indent=1))
    log("ex5 done")
except Exception as e:
    import traceback; traceback.print_exc()
    log("ex5 failed", repr(e))
