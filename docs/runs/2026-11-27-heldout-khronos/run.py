"""The held-out Khronos run: each sample rendered headless by wgpurender (wgpu path: `render --explain`; raw
Vulkan path: `reference`) and by pygfx 0.17 (offscreen), from one camera framed from the file's own numbers.

Usage (from the repository root, the venv's python, PYTHONPATH=.):
    python docs/runs/2026-11-27-heldout-khronos/run.py SAMPLES_DIR OUT_DIR [--only NAME ...]
SAMPLES_DIR holds the sample folders as the glTF-Sample-Assets repository lays them out under Models/
(NAME/VARIANT/files, NAME/README.md). Writes OUT_DIR/shots/*/{wgpu,raw,pygfx}.png and results.json; then
`table.py` joins it with verdicts.toml into results.csv and the contact sheets.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from gltf_view import frame, mesh_boxes, project  # noqa: E402
from lighting import BACKGROUND_LINEAR, scene_lights  # noqa: E402
from samples import SAMPLES  # noqa: E402

SIZE = 192


def scene_toml(model: str, cam: dict, sky: bool = False) -> str:
    environment = '[environment]\nprocedural = "sky"\n\n' if sky else ""
    return (f"{environment}[camera]\neye = {cam['eye']}\ntarget = {cam['target']}\nfov_y = {cam['fov_y']}\n"
            f"near = {cam['near']}\nfar = {cam['far']}\n\n"
            f"[render]\nsize = [{SIZE}, {SIZE}]\nmsaa = 4\nhdr = false\nclear_color = {list(BACKGROUND_LINEAR)}\n\n"
            f"{scene_lights()}\n[[models]]\npath = \"{model}\"\n")


def run(cmd: list[str], timeout: int = 300) -> dict:
    start = time.perf_counter()
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        rc, out, err = done.returncode, done.stdout, done.stderr
    except subprocess.TimeoutExpired:
        rc, out, err = 124, "", f"timed out after {timeout} s"
    return {"rc": rc, "stdout": out, "stderr": err.strip()[-2000:], "seconds": round(time.perf_counter() - start, 2)}


def probes(image_path: Path, boxes: list[np.ndarray], cam: dict) -> dict:
    """Which mesh boxes' projected centres are covered (differ from the background by more than 12/255); the
    samples' own probes (probes.py) run in table.py, on the saved images."""
    if not image_path.exists():
        return {}
    image = np.asarray(Image.open(image_path).convert("RGB")).astype(int)
    background = image[0, 0]
    covered = 0
    for box in boxes:
        col, row = project(box.mean(axis=0), cam, SIZE)
        if 0 <= col < SIZE and 0 <= row < SIZE:
            patch = image[max(row - 1, 0): row + 2, max(col - 1, 0): col + 2]
            covered += int(np.abs(patch - background).max() > 12)
    drawn = float((np.abs(image - background).max(axis=-1) > 12).mean())
    return {"centres_covered": covered, "boxes": len(boxes), "drawn_share": round(drawn, 4)}


def shoot(sample, samples_dir: Path, out: Path) -> dict:
    model = samples_dir / sample.file
    folder = out / "shots" / sample.key.replace("/", "-")
    folder.mkdir(parents=True, exist_ok=True)
    boxes = mesh_boxes(model)
    cam = frame(boxes, sample.view, zoom=sample.zoom)
    scene = model.parent / "heldout-scene.toml"
    scene.write_text(scene_toml(model.name, cam, sample.sky))
    py = sys.executable
    wgpu = run([py, "-m", "wgpurender", "render", str(scene), "--explain", "-o", str(folder / "wgpu.png")])
    raw = run([py, "-m", "wgpurender", "reference", str(scene), "-o", str(folder / "raw.png")])
    shot = [py, str(HERE / "pygfx_shot.py"), str(model), str(folder / "pygfx.png"), json.dumps(cam), str(SIZE)]
    peer = run(shot)
    if peer["rc"] < 0:  # killed by a signal: pygfx on lavapipe crashed once in 80 shots (signal 11); one retry
        peer = run(shot)
    ignored = [line.strip() for line in wgpu["stdout"].splitlines() if "ignored" in line]
    return {"file": sample.file, "feature": sample.feature, "right": sample.right, "camera": cam,
            "wgpu": {"rc": wgpu["rc"], "error": wgpu["stderr"] if wgpu["rc"] else "", "seconds": wgpu["seconds"],
                     "ignored": ignored, "probes": probes(folder / "wgpu.png", boxes, cam)},
            "raw": {"rc": raw["rc"], "error": raw["stderr"] if raw["rc"] else "", "seconds": raw["seconds"],
                    "probes": probes(folder / "raw.png", boxes, cam)},
            "pygfx": {"rc": peer["rc"], "error": peer["stderr"][-600:] if peer["rc"] else "",
                      "seconds": peer["seconds"], "probes": probes(folder / "pygfx.png", boxes, cam)}}


def main(argv: list[str]) -> int:
    samples_dir, out = Path(argv[0]), Path(argv[1])
    only = set(argv[argv.index("--only") + 1:]) if "--only" in argv else None
    out.mkdir(parents=True, exist_ok=True)
    results_path = out / "results.json"
    results = json.loads(results_path.read_text()) if results_path.exists() else {}
    for sample in SAMPLES:
        if only and sample.name not in only:
            continue
        key = sample.key
        print(key, flush=True)
        results[key] = shoot(sample, samples_dir, out)
        results_path.write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
