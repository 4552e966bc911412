"""Two more knobs for ``bench accuracy --truth analytic``, each against a float64 truth no renderer made:

- **mip chain**: the GPU's mip generation (wgpu_path/device/textures.generate_mipmaps) on an sRGB texture, read back
  level by level, against a float64 box-filtered pyramid in linear light (each level the mean of 2x2 texels of
  the one above, after decoding sRGB). Settings: ``linear light`` (the project's: an rgba8unorm-srgb texture,
  averaged after decoding), ``stored bytes`` (the same bytes uploaded as rgba8unorm: the encoded values are
  averaged, the classic gamma mistake), ``decimate`` (every other texel, no filter: the cheapest chain).
  Error: mean absolute linear error over every level below the base, each texel counted once; FLIP/PSNR of
  level 1. Time: wall ms to upload and build the chain (the CPU decimation is timed in numpy).
- **shading precision**: a lit plane (normalized Blinn-Phong, one point light, ambient; scene.wgsl's model)
  seen head-on, against the same model evaluated in float64 at every pixel centre. Settings: the scene image's
  format (rgba8unorm-srgb, rgba16float, rgba32float) before a post pass that changes nothing (a vignette of
  strength 0), so only the precision of the lit values differs.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from wgpurender.bench.accuracy_downsample import linear_from_srgb8, srgb8_from_linear
from wgpurender.bench.accuracy_knobs import Settings
from wgpurender.bench.accuracy_run import Measurement
from wgpurender.core.verdict.compare import compare_images
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.timing import Stats

MIP_SETTINGS = ("linear light", "stored bytes", "decimate")
SHADING_FORMATS = ("rgba8unorm-srgb", "rgba16float", "rgba32float")
PLANE = {"albedo": (0.6, 0.5, 0.4), "roughness": 0.5, "light": (0.3, 0.2, 1.0), "intensity": 1.5,
         "ambient": (0.03, 0.03, 0.035), "specular": 0.04, "fov": 45.0}


def mip_texture(n: int = 128) -> np.ndarray:
    """(n, n, 4) uint8 sRGB: fine stripes and a checker of saturated colours (where gamma matters most)."""
    ys, xs = np.mgrid[0:n, 0:n]
    rgb = np.where(((xs + ys) % 2 == 0)[..., None], [250, 20, 20], [10, 10, 240])
    rgb[(xs // 8 + ys // 8) % 2 == 0] = np.where(((xs % 2) == 0)[..., None], [255, 255, 255], [0, 0, 0])[
        (xs // 8 + ys // 8) % 2 == 0]
    return np.concatenate([rgb, np.full((n, n, 1), 255)], axis=-1).astype(np.uint8)


def box_pyramid(linear: np.ndarray) -> list[np.ndarray]:
    """Levels 0.. of a power-of-two (h, w, c) float64 image, each the mean of 2x2 texels of the one above."""
    levels = [np.asarray(linear, np.float64)]
    while min(levels[-1].shape[:2]) > 1:
        a = levels[-1]
        levels.append(0.25 * (a[0::2, 0::2] + a[1::2, 0::2] + a[0::2, 1::2] + a[1::2, 1::2]))
    return levels


def _gpu_chain(ctx: GPUContext, texels: np.ndarray, srgb: bool) -> list[np.ndarray]:
    from wgpurender.wgpu_path.device.textures import create_texture, read_mip

    texture = create_texture(ctx, texels, srgb=srgb, mips=True, label="accuracy-mips")
    return [read_mip(ctx, texture.texture, k) for k in range(texture.mip_level_count)]


def _decimated(texels: np.ndarray) -> list[np.ndarray]:
    levels = [texels]
    while min(levels[-1].shape[:2]) > 1:
        levels.append(levels[-1][::2, ::2])
    return levels


def _timed_chain(build, runs: int) -> tuple[list[np.ndarray], Stats]:
    times, levels = [], []
    for _ in range(max(runs, 1)):
        start = time.perf_counter()
        levels = build()
        times.append((time.perf_counter() - start) * 1e3)
    return levels, Stats.of(times)


def run_mip_chain(ctx: GPUContext, frames: int, row) -> list:
    """One row per setting (``row(section, setting, measurement, flip, psnr, mae)`` makes it)."""
    texels = mip_texture()
    truth = box_pyramid(linear_from_srgb8(texels)[..., :3])
    builds = {"linear light": lambda: _gpu_chain(ctx, texels, True),
              "stored bytes": lambda: _gpu_chain(ctx, texels, False),
              "decimate": lambda: _decimated(texels)}
    rows = []
    for setting in MIP_SETTINGS:
        levels, wall = _timed_chain(builds[setting], frames)
        errors = [np.abs(linear_from_srgb8(lv)[..., :3] - t) for lv, t in zip(levels[1:], truth[1:], strict=True)]
        mae = float(sum(e.sum() for e in errors) / sum(e.size for e in errors))
        c = compare_images(srgb8_from_linear(truth[1]), levels[1][..., :3])
        m = Measurement(levels[1], levels[1].shape[1::-1], wall, None)
        rows.append(row("mip chain", setting, m, c.flip_mean, c.psnr, mae))
    return rows


def plane_truth(size: tuple[int, int], intensity: float = PLANE["intensity"]) -> np.ndarray:
    """The lit plane's linear radiance at every pixel centre, in float64 (scene.wgsl's documented model)."""
    w, h = size
    d = 1.0 / np.tan(np.radians(PLANE["fov"]) / 2.0)
    ys, xs = np.mgrid[0:h, 0:w] + 0.5
    p = np.stack([(2 * xs / w - 1) * w / h, 1 - 2 * ys / h, np.zeros_like(xs)], axis=-1)
    n = np.array([0.0, 0.0, 1.0])
    to_light = np.asarray(PLANE["light"]) - p
    d2 = np.maximum((to_light**2).sum(-1), 1e-4)
    l_dir = to_light / np.sqrt(d2)[..., None]
    v = np.array([0.0, 0.0, d]) - p
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    half = l_dir + v
    half /= np.linalg.norm(half, axis=-1, keepdims=True)
    r4 = PLANE["roughness"] ** 4
    s = min(max(2.0 / max(r4, 1e-6) - 2.0, 1.0), 4096.0)
    n_dot_l = np.maximum(l_dir @ n, 0.0)
    spec = PLANE["specular"] * (s + 8.0) / 8.0 * np.maximum(half @ n, 0.0) ** s
    albedo, ambient = np.asarray(PLANE["albedo"]), np.asarray(PLANE["ambient"])
    irradiance = intensity / d2
    return ambient * albedo + (irradiance * n_dot_l)[..., None] * (albedo + spec[..., None])


def write_plane_scene(folder: Path, size: tuple[int, int], intensity: float = PLANE["intensity"],
                      post: str = 'effect = "vignette"\nstrength = 0.0', name: str = "plane") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    w, h = size
    a = w / h
    (folder / "plane.obj").write_text(f"v {-a} -1 0\nv {a} -1 0\nv {a} 1 0\nv {-a} 1 0\nvn 0 0 1\n"
                                      "f 1//1 2//1 3//1\nf 1//1 3//1 4//1\n")
    d = 1.0 / np.tan(np.radians(PLANE["fov"]) / 2.0)
    text = (f'description = "bench accuracy --truth analytic: a lit plane seen head-on"\n\n'
            f"[camera]\neye = [0.0, 0.0, {float(d)!r}]\ntarget = [0.0, 0.0, 0.0]\nfov_y = {PLANE['fov']}\n\n"
            f'[[models]]\npath = "plane.obj"\nmaterial = {{ albedo_color = {list(PLANE["albedo"])}, '
            f'roughness = {PLANE["roughness"]} }}\n\n'
            f'[[lights]]\ntype = "point"\nposition = {list(PLANE["light"])}\nintensity = {intensity}\n\n'
            f"[render]\nsize = [{w}, {h}]\nmsaa = 1\nhdr = true\nclear_color = [0.0, 0.0, 0.0, 1.0]\n"
            f'output_format = "rgba8unorm-srgb"\n\n[[post]]\n{post}\n')
    path = folder / f"{name}.toml"
    path.write_text(text)
    return path


def run_shading(ctx: GPUContext, work: Path, size: tuple[int, int], frames: int, warmup: int, timed, score) -> list:
    """One row per scene format; ``timed``/``score`` are accuracy_analytic's (the same renderer and timing)."""
    scene = write_plane_scene(work / "plane", size)
    truth = plane_truth(size)
    rows = []
    for fmt in SHADING_FORMATS:
        t = timed(ctx, scene, Settings(msaa=1, format=fmt), size, ("format",), frames, warmup)
        rows.append(score("shading precision", fmt, t, truth))
    return rows
