"""The six held-out animated samples played as the windows play them: each path's window loop against its own
offscreen render at ``--time`` (exact), the two loops against each other, and what a frame's ``play(t)`` costs.

For each sample (the heldout run's framing, lights, 192 px and msaa 4; no ``time`` in the model block): the plan's
clip end E (``RenderPlan.playing``), then a window-like loop on each path (the drawable built once, then
``play(t)`` and one frame per clock time, as wgpu_path/window and raw_path/window call them) over clock times
0, E/3 and E + E/3 (the last loops to E/3). Its last frame is compared with the same path's ``--time E/3`` render
(api.render / api.reference), and the two paths' last frames with each other. Then 20 further frames of the wgpu
loop at clock times spread over the clip give the median CPU time of ``play(t)`` (the re-pose and the writes).

Usage (repository root, the venv's python, PYTHONPATH=.:tests):
    python docs/runs/2026-11-27-play/run_play.py SAMPLES_DIR OUT_DIR
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
HELDOUT = HERE.parent / "2026-11-27-heldout-khronos"
sys.path.insert(0, str(HELDOUT))

from gltf_view import frame, mesh_boxes  # noqa: E402
from run import scene_toml  # noqa: E402
from samples import SAMPLES  # noqa: E402

NAMES = ("SimpleSkin", "RiggedSimple", "CesiumMan", "BoxAnimated", "AnimatedTriangle", "AnimatedMorphCube")
REACH = {"BoxAnimated": (0.0, 2.52, 0.0)}  # as anim-after/run_anim.py: the risen inner box stays in view


def measure(sample, samples_dir: Path) -> dict:
    from test_window_play import _raw_loop, _wgpu_loop

    from wgpurender import api
    from wgpurender.core.plan import resolve_plan
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.device.frame_loop import run_frame
    from wgpurender.wgpu_path.scene.frame import SceneRenderer

    model = samples_dir / sample.file
    boxes = mesh_boxes(model)
    reach = [box + np.array(REACH[sample.name]) for box in boxes] if sample.name in REACH else []
    scene = model.parent / "play-scene.toml"
    scene.write_text(scene_toml(model.name, frame(boxes + reach, sample.view, zoom=sample.zoom)))
    ctx = get_context()
    plan = resolve_plan(scene, ctx.adapter_facts())
    end = plan.playing[0].end
    local = end / 3
    times = [0.0, local, end + local]
    out = {"file": sample.file, "clip_end_s": end, "clock_times": times, "looped_to": local}
    for which, loop, draw in (("wgpu", lambda moved: _wgpu_loop(ctx, scene, times, moved), api.render),
                              ("raw", lambda moved: _raw_loop(scene, times, moved), api.reference)):
        moved = []
        pixels, writes = loop(moved)
        offscreen = draw(str(scene), t=local).pixels
        still = draw(str(scene), t=0.0).pixels  # the clip's start: the loop's frame must have moved from it
        out[which] = {"writes_per_frame": writes, "equal_to_offscreen": bool(np.array_equal(pixels, offscreen)),
                      "pixels_moved_from_t0": int(np.any(pixels != still, axis=-1).sum()),
                      "vertex_bytes_uploaded": moved[0],
                      "max_abs_diff_to_offscreen": int(np.abs(pixels.astype(int) - offscreen.astype(int)).max())}
        out[which + "_pixels"] = pixels
    out["wgpu_vs_raw_max_abs_diff"] = int(np.abs(out.pop("wgpu_pixels").astype(int)
                                                 - out.pop("raw_pixels").astype(int)).max())
    renderer = SceneRenderer(ctx, plan.scene, plan)
    target = renderer.create_output()
    costs = []
    for k in range(21):
        t = end * k / 21 + 1e-3
        start = time.perf_counter()
        renderer.play(t)
        costs.append((time.perf_counter() - start) * 1e3)
        run_frame(ctx, renderer.record, target, t)
    out["play_ms_median"] = round(float(np.median(costs[1:])), 3)
    out["vertices"] = int(sum(renderer.resources.meshes.mesh(key).vertex_count
                              for key in {d.mesh_key for d in plan.scene_pass.draws}))
    return out


def main(argv: list[str]) -> int:
    samples_dir, out = Path(argv[0]), Path(argv[1])
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    for sample in SAMPLES:
        if sample.name in NAMES and not sample.tag:
            print(sample.key, flush=True)
            results[sample.key] = measure(sample, samples_dir)
    (out / "results.json").write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
