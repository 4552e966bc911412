"""The five held-out skin and animation samples again (and AnimatedMorphCube's weights channel), each posed at a
chosen time on both paths and by pygfx.

The run of ../run.py (same framing from the file's own numbers, same lights, 192 px, msaa 4), with the model block
``time = T`` (core/models/gltf_animation.py: the file's first animation sampled at T, skins posed on the CPU) and
pygfx posed at the same T by its AnimationMixer (../pygfx_shot.py with T).

Usage (repository root, the venv's python, PYTHONPATH=.):
    python docs/runs/2026-11-27-heldout-khronos/anim-after/run_anim.py SAMPLES_DIR OUT_DIR
Writes OUT_DIR/shots/<sample>/{wgpu,raw,pygfx}.png, OUT_DIR/results.json and OUT_DIR/sheet.png (the samples
whose licence allows it; CesiumMan's does not).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from gltf_view import frame, mesh_boxes  # noqa: E402
from run import SIZE, probes, run, scene_toml  # noqa: E402
from samples import NO_SHEET, SAMPLES  # noqa: E402

# the time each sample is posed at: inside its keys, where its README's motion is well under way
TIMES = {"SimpleSkin": 2.0, "RiggedSimple": 1.0, "CesiumMan": 1.0, "BoxAnimated": 1.9, "AnimatedTriangle": 0.25,
         "AnimatedMorphCube": 2.5}  # the last: a weights channel (both morph targets part-way, 0.44 and 0.56)
# the framing also covers the rest boxes moved by this much: BoxAnimated's inner box rises by its translation
# channel's largest key (0, 2.52, 0) (keys 1.25-2.5 s; the rotation channel turns it 180 degrees about x then)
REACH = {"BoxAnimated": (0.0, 2.52, 0.0)}


def shoot(sample, t: float, samples_dir: Path, out: Path) -> dict:
    model = samples_dir / sample.file
    folder = out / "shots" / sample.key.replace("/", "-")
    folder.mkdir(parents=True, exist_ok=True)
    boxes = mesh_boxes(model)
    reach = [box + np.array(REACH[sample.name]) for box in boxes] if sample.name in REACH else []
    cam = frame(boxes + reach, sample.view, zoom=sample.zoom)
    scene = model.parent / "anim-scene.toml"
    scene.write_text(scene_toml(model.name, cam) + f"time = {t}\n")
    py = sys.executable
    wgpu = run([py, "-m", "wgpurender", "render", str(scene), "--explain", "-o", str(folder / "wgpu.png")])
    raw = run([py, "-m", "wgpurender", "reference", str(scene), "-o", str(folder / "raw.png")])
    peer = run([py, str(HERE.parent / "pygfx_shot.py"), str(model), str(folder / "pygfx.png"), json.dumps(cam),
                str(SIZE), str(t)])
    said = [line.strip() for line in wgpu["stdout"].splitlines()
            if "ignored" in line or "animation" in line or "skin" in line]
    images = {k: np.asarray(Image.open(folder / f"{k}.png").convert("RGB")).astype(int)
              for k in ("wgpu", "raw", "pygfx") if (folder / f"{k}.png").exists()}
    diff = {f"{a}-{b}": int(np.abs(images[a] - images[b]).max()) for a, b in (("wgpu", "raw"), ("wgpu", "pygfx"))
            if a in images and b in images}
    mask = {k: (np.abs(v - v[0, 0]).max(axis=-1) > 12) for k, v in images.items()}
    overlap = {}
    if "wgpu" in mask and "pygfx" in mask:  # silhouette agreement: intersection over union of the covered pixels
        union = (mask["wgpu"] | mask["pygfx"]).sum()
        overlap["wgpu-pygfx IoU"] = round(float((mask["wgpu"] & mask["pygfx"]).sum() / max(union, 1)), 4)
    return {"file": sample.file, "time": t, "camera": cam, "explain": said, "max_abs_diff": diff, **overlap,
            **{k: {"rc": r["rc"], "error": r["stderr"] if r["rc"] else "", "seconds": r["seconds"],
                   "probes": probes(folder / f"{k}.png", boxes, cam)}
               for k, r in (("wgpu", wgpu), ("raw", raw), ("pygfx", peer))}}


def sheet(out: Path, keys: list[str]) -> None:
    """wgpu | raw | pygfx per row, for the samples whose licence allows a picture in the repository."""
    rows = []
    for key in keys:
        folder = out / "shots" / key.replace("/", "-")
        row = [np.asarray(Image.open(folder / f"{k}.png").convert("RGB").resize((128, 128))) for k in
               ("wgpu", "raw", "pygfx")]
        rows.append(np.concatenate(row, axis=1))
    Image.fromarray(np.concatenate(rows, axis=0).astype(np.uint8)).save(out / "sheet.png", optimize=True)


def main(argv: list[str]) -> int:
    samples_dir, out = Path(argv[0]), Path(argv[1])
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    for sample in SAMPLES:
        if sample.name in TIMES:
            print(sample.key, flush=True)
            results[sample.key] = shoot(sample, TIMES[sample.name], samples_dir, out)
    (out / "results.json").write_text(json.dumps(results, indent=1))
    sheet(out, [k for k in results if k.split("/")[0] not in NO_SHEET])
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
