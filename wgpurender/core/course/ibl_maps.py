"""Image-based lighting maps in float64 numpy: the irradiance map, the GGX-prefiltered specular levels and the
split-sum BRDF table, made the way shaders_wgsl/ibl.wgsl's compute passes make them (the same texel layout, the
same Hammersley samples, the same tangent frame), so the GPU's maps can be checked against these.

Scenes draw with maps made on the GPU, on both paths the same way: compute passes that are twins operation for
operation (shaders_wgsl/ibl.wgsl on the wgpu path, wgpu_path/scene/ibl.py; shaders_glsl/ibl.comp on the raw
path, raw_path/scene/ibl.py), from the environment scene_environment() gives them. The float64 arrays here are
their check (tests/test_ibl_scene.py: relative 1e-4 where a sum is exact, 1% mean where a sample may land on a
texel edge) and what ``bench accuracy`` compares.

Layout of :func:`pack` (float32 vec4 rows, what the scene shaders index): the irradiance map (IRRADIANCE_SIZE, row
major, row 0 the zenith), then LEVELS prefiltered maps of PREFILTER_SIZE (level k at roughness k / (LEVELS - 1)),
then the LUT_SIZE x LUT_SIZE table (row: roughness, column: n.v; cells at their centres; (A, B, 0, 0)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wgpurender.core.course.environment import directions, texel_directions

IRRADIANCE_SIZE = (32, 16)  # (width, height)
PREFILTER_SIZE = (64, 32)
LEVELS = 5
LUT_SIZE = 32
SAMPLES = 256  # bench accuracy's best sample count on its Pareto front (docs/accuracy.md)
MAX_ENVIRONMENT = (256, 128)  # a larger environment is averaged down to this first (solid-angle weighted)
SAMPLE_CHOICES = (16, 64, 256, 1024)
# The compute passes that make the maps, in pack()'s order (ibl.wgsl's entry points; ibl.comp's -D variants are
# the names in capitals): each writes its region of the packed buffer.
PASSES = ("irradiance", "prefilter", "brdf_lut")


def pass_sizes() -> tuple[tuple[str, tuple[int, int], int], ...]:
    """(pass, (width, height), depth) of each compute pass: depth is the prefilter's levels, else 1."""
    return tuple(zip(PASSES, (IRRADIANCE_SIZE, PREFILTER_SIZE, (LUT_SIZE, LUT_SIZE)), (1, LEVELS, 1), strict=True))


@dataclass(frozen=True)
class IblArrays:
    irradiance: np.ndarray  # (h, w, 3) E / pi per normal direction
    prefiltered: np.ndarray  # (LEVELS, h, w, 3)
    lut: np.ndarray  # (n, n, 2) [roughness row, n.v column] -> (A, B)


def packed_rows() -> int:
    (iw, ih), (pw, ph) = IRRADIANCE_SIZE, PREFILTER_SIZE
    return iw * ih + LEVELS * pw * ph + LUT_SIZE * LUT_SIZE


def packed_bytes() -> int:
    return 16 * packed_rows()


# A storage binding's offset must be a multiple of the device's minStorageBufferOffsetAlignment: WebGPU's default
# limit is 256, and Vulkan allows no larger value, so a region starting at a multiple of 256 binds on any device.
REGION_ALIGN = 256


def regions(passes) -> tuple[list[int], int]:
    """Each pass's byte offset in one buffer of float32 vec4 texels, each at a multiple of :data:`REGION_ALIGN`,
    and the buffer's size; ``passes``: (pass, (width, height), depth) as :func:`pass_sizes` gives them."""
    offsets, end = [], 0
    for _, (width, height), depth in passes:
        offsets.append(end)
        end += -(-16 * width * height * depth // REGION_ALIGN) * REGION_ALIGN
    return offsets, end


def packed_regions() -> list[int]:
    """The byte offsets at which the compute passes write :func:`pack`'s layout (what the scene shaders index:
    the regions back to back): each must be a region start :func:`regions` allows, or a pass could not bind its
    region. ValueError when the sizes break that rule (each region a multiple of 16 texels)."""
    offsets, size = regions(pass_sizes())
    if size != packed_bytes():
        texels = ", ".join(f"{name} {w}x{h}x{depth}" for name, (w, h), depth in pass_sizes())
        raise ValueError(f"the image-based lighting maps ({texels} texels of 16 bytes) do not pack into regions "
                         f"starting at multiples of {REGION_ALIGN} bytes: make each map's texel count a multiple "
                         f"of {REGION_ALIGN // 16}")
    return offsets


def shrink(environment: np.ndarray, limit: tuple[int, int] = MAX_ENVIRONMENT) -> np.ndarray:
    """The environment at most ``limit`` (w, h): each target texel the solid-angle-weighted mean of the source
    texels whose centres fall inside it (equirectangular, so it keeps the mapping)."""
    h, w = environment.shape[:2]
    if w <= limit[0] and h <= limit[1]:
        return environment.astype(np.float64)
    tw, th = min(w, limit[0]), min(h, limit[1])
    _, omega = texel_directions(w, h)
    cols = ((np.arange(w) + 0.5) / w * tw).astype(int)
    rows = ((np.arange(h) + 0.5) / h * th).astype(int)
    index = (rows[:, None] * tw + cols[None, :]).reshape(-1)
    weights = np.bincount(index, omega.reshape(-1), th * tw)
    out = np.stack([np.bincount(index, (environment[..., c] * omega).reshape(-1), th * tw) for c in range(3)], -1)
    return (out / weights[:, None]).reshape(th, tw, 3)


def lookup(image: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The texel of an equirectangular (h, w, c) image holding direction d (..., 3) (ibl.wgsl's env_radiance)."""
    h, w = image.shape[:2]
    u = np.arctan2(d[..., 0], -d[..., 2]) / (2 * np.pi) + 0.5
    v = np.arccos(np.clip(d[..., 1], -1, 1)) / np.pi
    x = np.minimum((np.maximum(u, 0) * w).astype(int), w - 1)
    y = np.minimum((np.maximum(v, 0) * h).astype(int), h - 1)
    return image[y, x]


def hammersley(n: int) -> np.ndarray:
    """(n, 2): ((i + 0.5) / n, the bit-reversed i / 2^32)."""
    i = np.arange(n, dtype=np.uint64)
    bits = np.zeros(n, np.uint64)
    for b in range(32):
        bits |= ((i >> np.uint64(b)) & np.uint64(1)) << np.uint64(31 - b)
    return np.stack([(np.arange(n) + 0.5) / n, bits.astype(np.float64) * 2.0 ** -32], -1)


def ggx_half(xi: np.ndarray, alpha: float, n: np.ndarray) -> np.ndarray:
    """GGX half vectors (P, S, 3) around normals n (P, 3) for samples xi (S, 2) (pdf D(h) n.h)."""
    a2 = alpha * alpha
    phi = 2 * np.pi * xi[:, 0]
    cos_t = np.sqrt((1 - xi[:, 1]) / (1 + (a2 - 1) * xi[:, 1]))
    sin_t = np.sqrt(np.maximum(1 - cos_t * cos_t, 0))
    up = np.where((np.abs(n[:, 2]) < 0.999)[:, None], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    t = np.cross(up, n)
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    b = np.cross(n, t)
    h = (t[:, None] * (sin_t * np.cos(phi))[None, :, None] + b[:, None] * (sin_t * np.sin(phi))[None, :, None]
         + n[:, None] * cos_t[None, :, None])
    return h / np.linalg.norm(h, axis=-1, keepdims=True)


def _grid(size: tuple[int, int]) -> np.ndarray:
    w, h = size
    u, v = np.meshgrid((np.arange(w) + 0.5) / w, (np.arange(h) + 0.5) / h)
    return directions(u, v).reshape(-1, 3)


def irradiance(env: np.ndarray, size=IRRADIANCE_SIZE) -> np.ndarray:
    h, w = env.shape[:2]
    dirs, omega = texel_directions(w, h)
    weight = np.maximum(_grid(size) @ dirs.reshape(-1, 3).T, 0) * omega.reshape(-1)
    return (weight @ env.reshape(-1, 3) / np.pi).reshape(size[1], size[0], 3)


def mirror_level(env: np.ndarray, size=PREFILTER_SIZE) -> np.ndarray:
    """Level 0 (roughness 0, the mirror): each texel is the solid-angle-weighted mean of the environment texels
    whose centres fall inside it; where none does (an environment narrower or shorter than the map), the
    environment texel under its centre. Chosen by integer index arithmetic, which the GPU does exactly alike.

    Why not the GGX samples of the other levels: at roughness 0 they lie within ~2e-3 rad of the texel's
    centre, and a map half the environment's size has its centres on the environment's texel corners, so each
    texel was a blend of four texels set by the rounding of atan2 and acos (an H100 and lavapipe differed)."""
    h, w = env.shape[:2]
    pw, ph = size
    cols, rows = (2 * np.arange(w) + 1) * pw // (2 * w), (2 * np.arange(h) + 1) * ph // (2 * h)
    _, omega = texel_directions(w, h)
    index = (rows[:, None] * pw + cols[None, :]).reshape(-1)
    weight = np.bincount(index, omega.reshape(-1), pw * ph)
    total = np.stack([np.bincount(index, (env[..., c] * omega).reshape(-1), pw * ph) for c in range(3)], -1)
    under = env[((2 * np.arange(ph) + 1) * h // (2 * ph))[:, None], ((2 * np.arange(pw) + 1) * w // (2 * pw))[None]]
    mean = total / np.where(weight > 0, weight, 1.0)[:, None]
    return np.where((weight > 0)[:, None], mean, under.reshape(-1, 3)).reshape(ph, pw, 3)


def prefiltered(env: np.ndarray, samples: int, size=PREFILTER_SIZE, levels: int = LEVELS) -> np.ndarray:
    n, xi = _grid(size), hammersley(samples)
    out = [mirror_level(env, size)]
    for k in range(1, levels):
        roughness = k / max(levels - 1, 1)
        hv = ggx_half(xi, roughness * roughness, n)
        n_dot_h = np.einsum("pc,psc->ps", n, hv)
        light = 2 * n_dot_h[..., None] * hv - n[:, None]
        n_dot_l = np.einsum("pc,psc->ps", n, light)
        w = np.where(n_dot_l > 0, n_dot_l, 0.0)
        total = (lookup(env, light) * w[..., None]).sum(1) / np.maximum(w.sum(1), 1e-6)[:, None]
        out.append(total.reshape(size[1], size[0], 3))
    return np.stack(out)


def brdf_lut(samples: int, n_cells: int = LUT_SIZE) -> np.ndarray:
    """(A, B) with the height-correlated Smith V of pbr.wgsl: the integral of f n.l / F is f0 A + B."""
    with np.errstate(divide="ignore", invalid="ignore"):  # n.l <= 0 samples: masked out below
        return _lut(hammersley(samples), samples, n_cells)


def _lut(xi: np.ndarray, samples: int, n_cells: int) -> np.ndarray:
    out = np.zeros((n_cells, n_cells, 2))
    normal = np.array([[0.0, 0.0, 1.0]])
    for row in range(n_cells):
        alpha = ((row + 0.5) / n_cells) ** 2
        a2 = alpha * alpha
        hv = ggx_half(xi, alpha, normal)[0]  # (S, 3)
        nv = (np.arange(n_cells) + 0.5) / n_cells
        v = np.stack([np.sqrt(1 - nv * nv), np.zeros_like(nv), nv], -1)  # (C, 3)
        v_dot_h = v @ hv.T  # (C, S)
        light = 2 * v_dot_h[..., None] * hv[None] - v[:, None]
        nl, nh, vh = light[..., 2], np.maximum(hv[:, 2], 1e-6)[None], np.maximum(v_dot_h, 0)
        vis = 0.5 / (nl * np.sqrt(nv[:, None] ** 2 * (1 - a2) + a2) + nv[:, None] * np.sqrt(nl * nl * (1 - a2) + a2))
        g_vis = np.where(nl > 0, vis * 4 * nl * vh / nh, 0.0)
        fc = (1 - vh) ** 5
        out[row] = np.stack([((1 - fc) * g_vis).sum(1), (fc * g_vis).sum(1)], -1) / samples
    return out


def make_arrays(environment: np.ndarray, samples: int = SAMPLES) -> IblArrays:
    env = shrink(np.asarray(environment, np.float64))
    return IblArrays(irradiance(env), prefiltered(env, samples), brdf_lut(samples))


def pack(maps) -> np.ndarray:
    """(packed_rows(), 4) float32: the module docstring's layout, of any maps with the three arrays (IblArrays,
    or the wgpu path's IblMaps)."""
    rows = [maps.irradiance.reshape(-1, 3), maps.prefiltered.reshape(-1, 3)]
    rows = [np.concatenate([r, np.ones((len(r), 1))], -1) for r in rows]
    lut = maps.lut.reshape(-1, 2)
    rows.append(np.concatenate([lut, np.zeros((len(lut), 2))], -1))
    return np.ascontiguousarray(np.concatenate(rows), np.float32)


def scene_environment(environment) -> np.ndarray:
    """The (h, w, 3) float32 radiance a scene's [environment] (core/scene/environment_block.Environment) hands
    both paths' compute passes: averaged down to MAX_ENVIRONMENT first, as make_arrays does."""
    return shrink(environment.radiance()).astype(np.float32)


def scene_maps(environment) -> np.ndarray:
    """The packed float64 maps of a scene's [environment]: what the GPU's packed maps are checked against."""
    return pack(make_arrays(environment.radiance(), environment.samples))
