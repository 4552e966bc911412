"""``bench accuracy --truth analytic``'s image-based lighting section: the split-sum maps made on the GPU
(wgpu_path/scene/ibl.py) against a float64 integral of glTF's metallic-roughness BRDF over the same environment.

The test surface is a grid of normals on the visible half of a sphere seen along +z (v = (0, 0, 1)), for metallic
0 and 1 and roughness 0.25, 0.5 and 1 (BASE colour), lit only by the procedural sky (core/course/environment.py).
Truth: L(v) = integral of f(l, v) L_env(l) n.l over the sphere, summed in float64 over every environment texel cut
into SUB x SUB parts (each part its texel's radiance, its own direction and solid angle). Split sum (what a
renderer would draw): diffuse (1 - metallic) base E(n) / pi (1 - F(n.v)) + prefiltered(r, roughness) (f0 A + B),
the maps looked up at their nearest texel and interpolated linearly between roughness levels, the table
bilinearly. Settings: the GGX
sample count of the prefilter and the LUT; time: the wall time of the three compute passes (readback excluded).
"""

from __future__ import annotations

import numpy as np

from wgpurender.bench.accuracy_downsample import srgb8_from_linear
from wgpurender.bench.accuracy_run import Measurement
from wgpurender.core.course.environment import sky, texel_directions
from wgpurender.core.verdict.compare import compare_images
from wgpurender.wgpu_path.device.timing import Stats

SAMPLE_COUNTS = (16, 64, 256, 1024)
BASE = (0.9, 0.7, 0.4)
ROUGHNESS = (0.25, 0.5, 1.0)
METALLIC = (0.0, 1.0)
GRID = 7  # normals per side of the sphere patch
SUB = 2  # each environment texel cut into SUB x SUB parts for the truth


def sphere_normals(grid: int = GRID) -> np.ndarray:
    """(grid, grid, 3) unit normals of the front of a sphere seen along -z, at 0.9 of its radius at most."""
    s = np.linspace(-0.9, 0.9, grid) / np.sqrt(2)
    x, y = np.meshgrid(s, -s)
    return np.stack([x, y, np.sqrt(1 - x * x - y * y)], axis=-1)


def brdf64(n, to_light, v, metallic: float, roughness: float) -> np.ndarray:
    """glTF 2.0 Appendix B's BRDF (pbr.wgsl's form) in float64, (..., 3); ``to_light`` (..., 3) many directions."""
    a2 = (roughness * roughness) ** 2
    h = to_light + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    nl, nv = np.clip(to_light @ n, 0, 1), float(np.clip(n @ v, 0, 1))
    nh, vh = np.clip(h @ n, 0, 1), np.clip(h @ v, 0, 1)
    d = a2 / (np.pi * (nh * nh * (a2 - 1) + 1) ** 2)
    vis = 0.5 / np.maximum(nl * np.sqrt(nv * nv * (1 - a2) + a2) + nv * np.sqrt(nl * nl * (1 - a2) + a2), 1e-300)
    fc = ((1 - vh) ** 5)[..., None]
    base = np.asarray(BASE)
    f_dielectric = 0.04 + 0.96 * fc
    dielectric = (1 - f_dielectric) * base / np.pi + f_dielectric * (d * vis)[..., None]
    metal = (d * vis)[..., None] * (base + (1 - base) * fc)
    return np.where((nl > 0)[..., None], (1 - metallic) * dielectric + metallic * metal, 0.0)


def truth(environment: np.ndarray, normals: np.ndarray, metallic: float, roughness: float) -> np.ndarray:
    h, w = environment.shape[:2]
    dirs, omega = texel_directions(w, h, SUB)
    radiance = np.repeat(np.repeat(environment.astype(np.float64), SUB, axis=0), SUB, axis=1).reshape(-1, 3)
    dirs, omega = dirs.reshape(-1, 3), omega.reshape(-1)
    v = np.array([0.0, 0.0, 1.0])
    out = np.zeros(normals.shape)
    for idx in np.ndindex(normals.shape[:-1]):
        n = normals[idx]
        weight = (np.clip(dirs @ n, 0, 1) * omega)[:, None]
        out[idx] = (brdf64(n, dirs, v, metallic, roughness) * radiance * weight).sum(0)
    return out


def _lookup(image: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Nearest texel of an equirectangular (h, w, c) image in direction d (..., 3)."""
    h, w = image.shape[:2]
    u = np.arctan2(d[..., 0], -d[..., 2]) / (2 * np.pi) + 0.5
    v = np.arccos(np.clip(d[..., 1], -1, 1)) / np.pi
    return image[np.minimum((v * h).astype(int), h - 1), np.minimum((u * w).astype(int), w - 1)]


def _table(lut: np.ndarray, n_dot_v: np.ndarray, roughness: float) -> np.ndarray:
    """The BRDF table (cells at their centres) interpolated bilinearly at (n.v, roughness), clamped at the edges."""
    n = lut.shape[0]
    x, y = np.clip(n_dot_v * n - 0.5, 0, n - 1), float(np.clip(roughness * n - 0.5, 0, n - 1))
    x0, y0 = np.floor(x).astype(int), int(y)
    x1, y1, tx, ty = np.minimum(x0 + 1, n - 1), min(y0 + 1, n - 1), (x - x0)[..., None], y - y0
    rows = [(1 - tx) * lut[yy, x0] + tx * lut[yy, x1] for yy in (y0, y1)]
    return (1 - ty) * rows[0] + ty * rows[1]


def split_sum(maps, normals: np.ndarray, metallic: float, roughness: float) -> np.ndarray:
    v = np.array([0.0, 0.0, 1.0])
    nv = np.clip(normals @ v, 1e-4, 1)
    r = 2 * nv[..., None] * normals - v
    levels = len(maps.prefiltered)
    k = roughness * (levels - 1)
    k0, t = min(int(k), levels - 2), k - min(int(k), levels - 2)
    pre = (1 - t) * _lookup(maps.prefiltered[k0], r) + t * _lookup(maps.prefiltered[k0 + 1], r)
    ab = _table(maps.lut, nv, roughness)
    base = np.asarray(BASE)
    f0 = (1 - metallic) * 0.04 + metallic * base
    fresnel = (0.04 + 0.96 * (1 - nv) ** 5)[..., None]
    diffuse = (1 - metallic) * base * _lookup(maps.irradiance, normals) * (1 - fresnel)
    return diffuse + pre * (f0 * ab[..., :1] + ab[..., 1:])


def tile(images: list[np.ndarray]) -> np.ndarray:
    return np.concatenate(images, axis=1)


def run_ibl(ctx, frames: int, row, environment: np.ndarray | None = None) -> list:
    """One row per sample count (``row(section, setting, measurement, flip, psnr, mae, note=)``): the mean
    absolute linear error of the split-sum radiance over the test surface (relative to the mean radiance in the
    note), FLIP/PSNR of the tiled sRGB images, the compute passes' time."""
    from wgpurender.wgpu_path.scene.ibl import make_maps

    environment = sky() if environment is None else environment
    normals = sphere_normals()
    cases = [(m, r) for m in METALLIC for r in ROUGHNESS]
    exact = tile([truth(environment, normals, m, r) for m, r in cases])
    rows = []
    for samples in SAMPLE_COUNTS:
        times, maps = [], None
        for _ in range(max(frames, 1)):
            maps = make_maps(ctx, environment, samples)
            times.append(maps.gpu_wall_ms)
        got = tile([split_sum(maps, normals, m, r) for m, r in cases])
        mae = float(np.mean(np.abs(got - exact)))
        c = compare_images(srgb8_from_linear(np.clip(exact, 0, 1)), srgb8_from_linear(np.clip(got, 0, 1)))
        pixels = srgb8_from_linear(np.clip(got, 0, 1))
        m = Measurement(pixels, pixels.shape[1::-1], Stats.of(times), None)
        rows.append(row("image-based lighting", f"{samples} samples", m, c.flip_mean, c.psnr, mae,
                        note=f"relative error {mae / float(np.mean(exact)):.2%}"))
        rows.append(_cpu_row(environment, normals, cases, exact, samples, frames, row))
    return rows


def _cpu_row(environment, normals, cases, exact, samples: int, frames: int, row):
    """The same maps made in float64 numpy (core/course/ibl_maps.py: the check of the GPU maps scenes draw);
    time: the CPU wall time of making them (reported in the wall column, no GPU time)."""
    import time

    from wgpurender.core.course.ibl_maps import make_arrays

    times, maps = [], None
    for _ in range(max(frames, 1)):
        start = time.perf_counter()
        maps = make_arrays(environment, samples)
        times.append((time.perf_counter() - start) * 1e3)
    got = tile([split_sum(maps, normals, m, r) for m, r in cases])
    mae = float(np.mean(np.abs(got - exact)))
    c = compare_images(srgb8_from_linear(np.clip(exact, 0, 1)), srgb8_from_linear(np.clip(got, 0, 1)))
    pixels = srgb8_from_linear(np.clip(got, 0, 1))
    m = Measurement(pixels, pixels.shape[1::-1], Stats.of(times), None)
    return row("image-based lighting", f"{samples} samples, float64 CPU (the check)", m, c.flip_mean, c.psnr, mae,
               note=f"relative error {mae / float(np.mean(exact)):.2%}; time: CPU wall ms")
