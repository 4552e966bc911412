"""Khronos Cameras rendered through each of its two cameras: wgpurender's wgpu and raw paths, and pygfx 0.17.

Usage (repository root): python docs/runs/2026-11-27-heldout-khronos/cameras-after/shots.py CAMERAS.gltf OUT

Writes OUT/scene-K.toml, OUT/explain-K.txt, OUT/{wgpu,raw,pygfx,pygfx-units}-K.png, OUT/measured.csv and
OUT/sheet.png (rows: camera 0, camera 1; columns: wgpu, raw, pygfx, pygfx-units), beside a copy of the model.
The probe is this script's own float64 ray cast, from the file's numbers only (the square's POSITION min/max,
node 0's rotation, the camera nodes' translations, the cameras' projections): each pixel centre covered or not
by the square, compared where the pixel's four inner points (+-0.45 px) agree, the pixel counted as drawn where
it differs from the grey background by more than 32/255 in some channel.
"""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from lighting import BACKGROUND_LINEAR, BACKGROUND_SRGB, LIGHT_DIRECTION, scene_lights  # noqa: E402

SIZE = 192


def scene_toml(model: Path, k: int) -> str:
    return (f"[camera]\nfrom_model = 0\nfile_camera = {k}\n\n[render]\nsize = [{SIZE}, {SIZE}]\nmsaa = 4\n"
            f"hdr = false\nclear_color = {list(BACKGROUND_LINEAR)}\n\n{scene_lights()}\n[[models]]\n"
            f'path = "{model.name}"\n')


def quaternion_matrix(q) -> np.ndarray:
    x, y, z, w = np.asarray(q, np.float64) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def expected(doc: dict, k: int, offset=(0.0, 0.0)) -> np.ndarray:
    """Whether each pixel (centre moved by ``offset``) sees the square, by the file's numbers."""
    lo, hi = (np.array(doc["accessors"][1][key], np.float64) for key in ("min", "max"))
    rot = quaternion_matrix(doc["nodes"][0]["rotation"])  # the square's node: rotation only
    node = next(n for n in doc["nodes"] if n.get("camera") == k)
    eye = np.array(node["translation"], np.float64)  # the camera nodes: translation only
    cam = doc["cameras"][k]
    rows, cols = np.mgrid[0:SIZE, 0:SIZE] + 0.5
    x, y = (cols + offset[0]) / SIZE * 2 - 1, 1 - (rows + offset[1]) / SIZE * 2
    if cam["type"] == "perspective":
        t = math.tan(cam["perspective"]["yfov"] / 2)
        aspect = cam["perspective"].get("aspectRatio", 1.0)
        origin = np.broadcast_to(eye, (SIZE, SIZE, 3))
        direction = np.stack([x * t * aspect, y * t, -np.ones_like(x)], axis=-1)
    else:
        o = cam["orthographic"]
        origin = eye + np.stack([x * o["xmag"], y * o["ymag"], np.zeros_like(x)], axis=-1)
        direction = np.broadcast_to([0.0, 0.0, -1.0], (SIZE, SIZE, 3))
    # into the square's local frame (z = 0 there): p_local = rot^T p
    o_local, d_local = origin @ rot, direction @ rot
    t_hit = -o_local[..., 2] / d_local[..., 2]
    hit = o_local + t_hit[..., None] * d_local
    inside = (hit[..., 0] > lo[0]) & (hit[..., 0] < hi[0]) & (hit[..., 1] > lo[1]) & (hit[..., 1] < hi[1])
    return inside & (t_hit > 0)


def probe(image: np.ndarray, doc: dict, k: int) -> dict:
    """Pixels probed (inner points +-0.45 px agree), of them expected covered, and drawn otherwise; and drawn
    otherwise among the pixels whose points +-1.5 px agree too (more than a pixel from any edge)."""
    want = expected(doc, k)
    background = np.round(np.asarray(BACKGROUND_SRGB[:3]) * 255)
    drawn = np.abs(image[..., :3].astype(np.float64) - background).max(axis=-1) > 32
    out = {}
    for name, reach in (("", 0.45), ("_beyond_1px", 1.5)):
        sure = np.ones_like(want)
        for dx in (-reach, reach):
            for dy in (-reach, reach):
                sure &= expected(doc, k, (dx, dy)) == want
        if not name:
            out.update(probed=int(sure.sum()), covered_expected=int((want & sure).sum()))
        out[f"wrong{name}"] = int(((drawn != want) & sure).sum())
    return out


def pygfx_shots(model: Path, out: Path) -> None:
    """pygfx 0.17 through each camera its glTF loader made (gfx.load_gltf(...).cameras, in node order), and through
    the same camera made here with pygfx's units (PerspectiveCamera's fov is in degrees, glTF's yfov in radians;
    OrthographicCamera's width and height are full extents, glTF's xmag and ymag half extents) at the loaded pose:
    a second, independent renderer of the file's cameras."""
    code = f"""
import numpy as np, pygfx as gfx, sys
sys.path.insert(0, {str(HERE.parent)!r})
from lighting import pygfx_lights
from PIL import Image
from rendercanvas.offscreen import RenderCanvas
loaded = gfx.load_gltf({str(model)!r}, quiet=True, remote_ok=False)
import json, math
numbers = json.load(open({str(model)!r}))["cameras"]
shots = []
for k, camera in enumerate(loaded.cameras):
    shots.append((f"pygfx-{{k}}", camera))
    # the same camera made with pygfx's own units (fov in degrees, full width and height), at the loaded pose
    c = numbers[k]
    if c["type"] == "perspective":
        p = c["perspective"]
        fixed = gfx.PerspectiveCamera(math.degrees(p["yfov"]), p.get("aspectRatio", 1.0),
                                      depth_range=(p["znear"], p.get("zfar", 1e6)))
    else:
        o = c["orthographic"]
        fixed = gfx.OrthographicCamera(2 * o["xmag"], 2 * o["ymag"], depth_range=(o["znear"], o["zfar"]))
    fixed.local.matrix = camera.world.matrix
    shots.append((f"pygfx-units-{{k}}", fixed))
for name, camera in shots:
    canvas = RenderCanvas(size=({SIZE}, {SIZE}), pixel_ratio=1)
    renderer = gfx.WgpuRenderer(canvas)
    scene = gfx.Scene()
    scene.add(gfx.Background.from_color({BACKGROUND_SRGB}))
    scene.add(loaded.scene)
    for light in pygfx_lights(np.array([0.5, 0.5, 0.0]), {LIGHT_DIRECTION}):
        scene.add(light)
    canvas.request_draw(lambda: renderer.render(scene, camera))
    Image.fromarray(np.asarray(canvas.draw())[:, :, :3]).save({str(out)!r} + f"/{{name}}.png")
    print(name, type(camera).__name__, "fov", getattr(camera, "fov", None), "width", camera.width, "height",
          camera.height, "world position", camera.world.position.tolist())
"""
    print(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300).stdout, end="")


def main(source: str, out: str) -> int:
    out = Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    doc = json.loads(Path(source).read_text())
    model = out / Path(source).name  # a copy beside the scenes: a scene reads models under its own folder
    model.write_text(Path(source).read_text())
    py = sys.executable
    for k in range(len(doc["cameras"])):
        scene = out / f"scene-{k}.toml"
        scene.write_text(scene_toml(model, k))
        done = subprocess.run([py, "-m", "wgpurender", "render", str(scene), "--explain", "-o",
                               str(out / f"wgpu-{k}.png")], check=True, capture_output=True, text=True)
        (out / f"explain-{k}.txt").write_text(done.stdout.replace(str(out), "OUT"))  # no machine path
        subprocess.run([py, "-m", "wgpurender", "reference", str(scene), "-o", str(out / f"raw-{k}.png")], check=True,
                       stdout=subprocess.DEVNULL)
    pygfx_shots(model, out)
    rows, sheet = [], []
    for k in range(len(doc["cameras"])):
        images = {r: np.asarray(Image.open(out / f"{r}-{k}.png").convert("RGB"))
                  for r in ("wgpu", "raw", "pygfx", "pygfx-units")}
        for renderer, image in images.items():
            rows.append({"camera": k, "type": doc["cameras"][k]["type"], "renderer": renderer, **probe(image, doc, k),
                         "max_abs_vs_wgpu": int(np.abs(image.astype(int) - images["wgpu"].astype(int)).max())})
        gap = np.full((SIZE, 4, 3), 255, np.uint8)
        sheet.append(np.concatenate([images["wgpu"], gap, images["raw"], gap, images["pygfx"], gap,
                                     images["pygfx-units"]], axis=1))
    with open(out / "measured.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    Image.fromarray(np.concatenate([sheet[0], np.full((4, sheet[0].shape[1], 3), 255, np.uint8), sheet[1]])).save(
        out / "sheet.png")
    for row in rows:
        print(row)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:3]))
