"""``bench accuracy --truth analytic``: five knobs against ground truths that no renderer made.

- **Anti-aliasing**, the SMAA paper's protocol (Jimenez et al. 2012: error against a reference, and cost in
  ms): none, FXAA, MSAA 4x, SSAA 2x and 4x (and MSAA 4x + FXAA) on flat-coloured triangles of known
  geometry (slivers near horizontal and vertical, a large triangle, sub-pixel triangles), against their
  exact per-pixel coverage (accuracy_truth.polygon_coverage).
- **Texture filtering**: nearest, linear, trilinear, anisotropic 4x and 16x on a ground plane seen at a
  grazing angle, against the float64 integral of the bilinearly reconstructed texture over each pixel's
  footprint (accuracy_truth.footprint_average).
- **Depth**: depth24plus, depth32float and reverse-Z on the depth-stress scene (accuracy_depth.py), whose
  exact image is known (the near quad everywhere).

- **Mip chain** and **shading precision** (accuracy_fidelity.py): the GPU's mip generation against a float64
  box-filtered pyramid in linear light, and the lit result in each scene-image format against float64 lighting.

Within each knob the Pareto front (time against mean linear error: the settings no other setting of that knob
beats on both) is marked. Each setting goes through the real scene renderer (accuracy_knobs.make_renderer) and
is timed like the main sweep (GPU timestamps and wall time per frame). Errors: FLIP and PSNR of the 8-bit sRGB
image against the truth, and the mean absolute error in linear light.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wgpurender.bench import accuracy_truth as truth
from wgpurender.bench.accuracy_depth import analytic_image, write_depth_scene
from wgpurender.bench.accuracy_downsample import linear_from_srgb8, srgb8_from_linear
from wgpurender.bench.accuracy_knobs import DEPTH_LEVELS, FILTER_LEVELS, Settings
from wgpurender.bench.accuracy_run import Measurement, Timed
from wgpurender.core.models.procedural import MeshArrays, write_obj
from wgpurender.core.verdict.compare import compare_images
from wgpurender.wgpu_path.device.context import GPUContext

FOV = 45.0
BACKGROUND = (0.02, 0.025, 0.04)
# Triangles in units of the image size (x right, y down), flat colours (linear), none overlapping.
TRIANGLES = [
    (((0.04, 0.08), (0.96, 0.15), (0.04, 0.12)), (0.9, 0.9, 0.85)),  # a long sliver, nearly horizontal
    (((0.08, 0.25), (0.12, 0.92), (0.16, 0.25)), (0.95, 0.3, 0.1)),  # a tall sliver, nearly vertical
    (((0.25, 0.3), (0.62, 0.9), (0.7, 0.35)), (0.1, 0.7, 0.25)),  # a large triangle with oblique edges
    (((0.75, 0.3), (0.95, 0.28), (0.8, 0.85)), (0.2, 0.35, 0.95)),  # another, steep edges
    (((0.3, 0.2), (0.5, 0.24), (0.5, 0.22)), (0.95, 0.85, 0.2)),  # a thin wedge
]
SUBPIXEL = [((0.20 + 0.05 * i, 0.95), (0.212 + 0.05 * i, 0.958), (0.203 + 0.05 * i, 0.962)) for i in range(6)]
AA_SETTINGS = {  # label -> (msaa, ss, fxaa)
    "none": (1, 1, False), "fxaa": (1, 1, True), "msaa4": (4, 1, False), "ssaa2": (1, 2, False),
    "ssaa4": (1, 4, False), "msaa4+fxaa": (4, 1, True),
}
GROUND = {"eye": (0.0, 2.0, 0.0), "target": (0.0, 0.0, -2.5), "uv_per_unit": 0.75, "tex": 64}


@dataclass
class TruthRow:
    section: str
    setting: str
    m: Measurement
    flip: float
    psnr: float
    linear_mae: float
    note: str = ""
    pareto: bool = False

    def time_ms(self) -> float:
        """GPU median where timestamps exist, else the wall median: what the Pareto front weighs."""
        return self.m.gpu.median if self.m.gpu else self.m.wall.median


def _view_distance() -> float:
    return 1.0 / np.tan(np.radians(FOV) / 2.0)


def _to_world(points: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Image-fraction points -> the z = 0 plane seen exactly filling a FOV-degree view from (0, 0, d)."""
    w, h = size
    return np.stack([(points[:, 0] * 2 - 1) * w / h, 1 - points[:, 1] * 2, np.zeros(len(points))], axis=-1)


def _triangle_obj(path: Path, world: np.ndarray) -> Path:
    a, b, c = world
    if np.cross(b - a, c - a)[2] < 0:  # counter-clockwise seen from +Z, the camera's side
        world = world[[0, 2, 1]]
    mesh = MeshArrays(world, np.tile([0.0, 0.0, 1.0], (3, 1)), np.zeros((3, 2)), np.array([[0, 1, 2]]))
    return write_obj(path, mesh)


def triangle_shapes(size: tuple[int, int]) -> list[tuple[np.ndarray, np.ndarray, tuple]]:
    """Every flat shape of the AA scene: (world vertices as the OBJ holds them, pixel vertices, linear colour)."""
    w, h = size
    out = []
    for points, colour in TRIANGLES + [(s, (0.95, 0.95, 0.95)) for s in SUBPIXEL]:
        world = np.round(_to_world(np.array(points), size), 6)  # what the OBJ holds (6 decimals)
        px = np.stack([(world[:, 0] * h / w + 1) / 2 * w, (1 - world[:, 1]) / 2 * h], axis=-1)
        out.append((world, px, colour))
    return out


def write_triangles_scene(folder: Path, size: tuple[int, int], fxaa: bool) -> tuple[Path, np.ndarray]:
    """The AA scene file, and its exact linear image at ``size``."""
    folder.mkdir(parents=True, exist_ok=True)
    models, coverages, colours = [], [], []
    for i, (world, px, colour) in enumerate(triangle_shapes(size)):
        obj = _triangle_obj(folder / f"tri{i}.obj", world)
        coverages.append(truth.polygon_coverage(px, size))
        colours.append(colour)
        material = f"{{ albedo_color = {list(colour)}, unlit = true }}"
        models.append(f'[[models]]\npath = "{obj.name}"\nmaterial = {material}\n')
    post = '\n[[post]]\neffect = "fxaa"\n' if fxaa else ""
    text = (f'description = "bench accuracy --truth analytic: flat triangles of known coverage"\n\n[camera]\n'
            f"eye = [0.0, 0.0, {float(_view_distance())!r}]\ntarget = [0.0, 0.0, 0.0]\nfov_y = {FOV}\n\n"
            + "\n".join(models)
            + f"\n[render]\nsize = [{size[0]}, {size[1]}]\nmsaa = 1\nhdr = {str(fxaa).lower()}\n"
            f"clear_color = [{BACKGROUND[0]}, {BACKGROUND[1]}, {BACKGROUND[2]}, 1.0]\n"
            f'output_format = "rgba8unorm-srgb"\n' + post)
    path = folder / ("triangles_fxaa.toml" if fxaa else "triangles.toml")
    path.write_text(text)
    return path, truth.composite(coverages, colours, BACKGROUND)


def ground_texture(n: int) -> np.ndarray:
    """(n, n, 4) uint8 sRGB: a 2-texel checker of two colours with a thin diagonal stripe, full of detail."""
    ys, xs = np.mgrid[0:n, 0:n]
    checker = ((xs // 2 + ys // 2) % 2).astype(bool)
    rgb = np.where(checker[..., None], [230, 140, 40], [30, 60, 160])
    rgb[(xs - ys) % 16 == 0] = [250, 250, 250]
    return np.concatenate([rgb, np.full((n, n, 1), 255)], axis=-1).astype(np.uint8)


def write_ground_scene(folder: Path, size: tuple[int, int], n_sub: int = 16) -> tuple[Path, np.ndarray]:
    """The filtering scene (an unlit textured ground plane at a grazing angle) and its exact linear image."""
    from wgpurender.core.files.imageio import save_png

    folder.mkdir(parents=True, exist_ok=True)
    texels = ground_texture(GROUND["tex"])
    save_png(folder / "ground.png", texels)
    k, extent = GROUND["uv_per_unit"], 40.0
    corners = np.array([[-extent, 0, -extent], [extent, 0, -extent], [extent, 0, extent], [-extent, 0, extent]])
    mesh = MeshArrays(corners, np.tile([0.0, 1.0, 0.0], (4, 1)), corners[:, [0, 2]] * k,
                      np.array([[0, 2, 1], [0, 3, 2]]))  # counter-clockwise seen from above
    write_obj(folder / "ground.obj", mesh)
    eye, target = GROUND["eye"], GROUND["target"]
    text = (f'description = "bench accuracy --truth analytic: a textured ground plane at a grazing angle"\n\n'
            f"[camera]\neye = {list(eye)}\ntarget = {list(target)}\nfov_y = {FOV}\nnear = 0.05\nfar = 200.0\n\n"
            f'[[models]]\npath = "ground.obj"\nmaterial = {{ albedo_map = "ground.png", unlit = true, '
            f'sampler = {{ filter = "linear", mipmaps = true, address_mode = "repeat" }} }}\n\n'
            f"[render]\nsize = [{size[0]}, {size[1]}]\nmsaa = 1\nhdr = false\n"
            f'output_format = "rgba8unorm-srgb"\n')
    path = folder / "ground.toml"
    path.write_text(text)
    texture_linear = linear_from_srgb8(texels)[..., :3]
    return path, truth.footprint_average(texture_linear, eye, target, FOV, size, k, n_sub)


def _score(section: str, setting: str, t: Timed, truth_linear: np.ndarray, note: str = "") -> TruthRow:
    m = t.measurement()
    truth8 = srgb8_from_linear(truth_linear)
    c = compare_images(truth8, m.pixels[..., :3])
    mae = float(np.abs(linear_from_srgb8(m.pixels)[..., :3] - truth_linear).mean())
    return TruthRow(section, setting, m, c.flip_mean, c.psnr, mae, note)


def _timed(ctx: GPUContext, scene_path: Path, settings: Settings, size, knobs, frames: int, warmup: int) -> Timed:
    from wgpurender.core.scene import load_scene

    t = Timed(ctx, load_scene(scene_path), settings, size, knobs)
    t.run(frames, warmup=warmup)
    t.read()
    return t


def run_analytic(ctx: GPUContext, out_dir: Path, size: tuple[int, int], frames: int, warmup: int,
                 progress=print, ibl: bool = True) -> list[TruthRow]:
    """Render, time and score the sections (``ibl``: with image-based lighting's, bench/accuracy_ibl.py);
    returns the rows in report order."""
    rows: list[TruthRow] = []
    work = out_dir / "analytic_scenes"
    plain, aa_truth = write_triangles_scene(work, size, fxaa=False)
    with_fxaa, _ = write_triangles_scene(work, size, fxaa=True)
    for label, (msaa, ss, fxaa) in AA_SETTINGS.items():
        settings = Settings(msaa=msaa, ss=ss)
        t = _timed(ctx, with_fxaa if fxaa else plain, settings, size, ("msaa", "ss"), frames, warmup)
        rows.append(_score("anti-aliasing", label, t, aa_truth))
        progress(f"anti-aliasing {label}: FLIP {rows[-1].flip:.4f}")
    ground, ground_truth = write_ground_scene(work, size)
    for level in FILTER_LEVELS:
        t = _timed(ctx, ground, Settings(msaa=1, filter=level), size, ("filter",), frames, warmup)
        rows.append(_score("texture filtering", level, t, ground_truth))
        progress(f"texture filtering {level}: FLIP {rows[-1].flip:.4f}")
    depth_scene = write_depth_scene(work / "depth_stress", size)
    exact = linear_from_srgb8(analytic_image(size))[..., :3]
    for level in DEPTH_LEVELS:
        t = _timed(ctx, depth_scene, Settings(msaa=1, depth=level), size, ("depth",), frames, warmup)
        rows.append(_score("depth", level, t, exact))
        progress(f"depth {level}: FLIP {rows[-1].flip:.4f}")
    from wgpurender.bench import accuracy_fidelity, accuracy_hdr

    for row in (accuracy_fidelity.run_mip_chain(ctx, frames, TruthRow)
                + accuracy_fidelity.run_shading(ctx, work, size, frames, warmup, _timed, _score)
                + accuracy_hdr.run_hdr(ctx, work, size, frames, warmup, _timed, _score)):
        rows.append(row)
        progress(f"{row.section} {row.setting}: mean linear error {row.linear_mae:.5f}")
    if ibl:
        from wgpurender.bench.accuracy_ibl import run_ibl

        for row in run_ibl(ctx, frames, TruthRow):
            rows.append(row)
            progress(f"{row.section} {row.setting}: mean linear error {row.linear_mae:.5f} ({row.note})")
    return mark_pareto(rows)


def mark_pareto(rows: list[TruthRow]) -> list[TruthRow]:
    """Set ``pareto`` on the rows no other row of the same knob beats on both time and mean linear error."""
    from wgpurender.bench.accuracy_pareto import pareto_front

    for section in dict.fromkeys(r.section for r in rows):
        group = [r for r in rows if r.section == section]
        for i in pareto_front([(r.time_ms(), r.linear_mae) for r in group]):
            group[i].pareto = True
    return rows


CSV_COLUMNS = ("section", "setting", "render_size", "flip_mean", "psnr_db", "linear_mae", "gpu_ms_median",
               "gpu_ms_p10", "gpu_ms_p90", "wall_ms_median", "frames", "pareto", "timing")


def _num(v: float | None, digits: int) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return ""
    return "inf" if math.isinf(v) else f"{v:.{digits}f}"


def write_analytic_reports(rows: list[TruthRow], out_dir: Path, header: list[str], floor=None) -> dict[str, Path]:
    """accuracy_analytic.csv and accuracy_analytic.md in ``out_dir``; ``floor``: the run's accuracy_floor.Floor."""
    from wgpurender.bench.accuracy_floor import BELOW

    def below(r: TruthRow) -> bool:
        return floor is not None and floor.below(r.m.gpu.median if r.m.gpu else None, r.m.wall.median)

    out_dir.mkdir(parents=True, exist_ok=True)
    csv_path, md_path = out_dir / "accuracy_analytic.csv", out_dir / "accuracy_analytic.md"
    with csv_path.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(CSV_COLUMNS)
        for r in rows:
            g = r.m.gpu
            writer.writerow([r.section, r.setting, f"{r.m.render_size[0]}x{r.m.render_size[1]}", _num(r.flip, 5),
                             _num(r.psnr, 2), _num(r.linear_mae, 5), _num(g.median if g else None, 3),
                             _num(g.p10 if g else None, 3), _num(g.p90 if g else None, 3),
                             _num(r.m.wall.median, 3), r.m.wall.n, "yes" if r.pareto else "",
                             BELOW if below(r) else ""])
    lines = [*header, "", "Pareto: within each knob, no other setting is both faster and closer to the truth (time: "
             "GPU median where timestamps exist, else wall; error: mean absolute linear error).", "",
             "| knob | setting | render | FLIP | PSNR dB | mean abs. error (linear) | GPU ms | wall ms | Pareto |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        g = r.m.gpu
        gpu = f"{g.median:.2f} ({g.p10:.2f}..{g.p90:.2f})" if g else "-"
        wall = f"{r.m.wall.median:.2f}"
        if below(r):  # the time the front weighs (GPU where measured) says "below", the other keeps its number
            gpu, wall = (BELOW, wall) if g else (gpu, BELOW)
        lines.append(f"| {r.section} | {r.setting} | {r.m.render_size[0]}x{r.m.render_size[1]} | {r.flip:.4f} | "
                     f"{_num(r.psnr, 2)} | {r.linear_mae:.5f} | {gpu} | {wall} | "
                     f"{'**front**' if r.pareto else ''} |")
    if floor is not None:
        lines += ["", f"- {floor.describe()}"]
    md_path.write_text("\n".join(lines) + "\n")
    return {"csv": csv_path, "markdown": md_path}
