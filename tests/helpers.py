"""Independent references for the tests: rasterisation and interpolation in float64 numpy."""

from __future__ import annotations

import numpy as np

# The standard 4x sample positions of Vulkan/D3D (VkPhysicalDeviceLimits::standardSampleLocations),
# in pixel units from the pixel's top-left corner.
STANDARD_4X = np.array([[0.375, 0.125], [0.875, 0.375], [0.125, 0.625], [0.625, 0.875]])


def ndc_to_pixels(ndc: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """wgpu's viewport transform: NDC x right / y up to pixels x right / y down."""
    w, h = size
    ndc = np.asarray(ndc, dtype=np.float64)
    return np.stack([(ndc[:, 0] + 1) * 0.5 * w, (1 - ndc[:, 1]) * 0.5 * h], axis=1)


def barycentric(tri_px: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Barycentric weights (N, 3) of ``points`` (N, 2) in a pixel-space triangle."""
    a, b, c = tri_px
    m = np.array([[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]])
    uv = np.linalg.solve(m, (np.asarray(points, dtype=np.float64) - a).T).T
    return np.column_stack([1 - uv.sum(axis=1), uv[:, 0], uv[:, 1]])


def pixel_centres(size: tuple[int, int]) -> np.ndarray:
    w, h = size
    ys, xs = np.mgrid[0:h, 0:w]
    return np.stack([xs + 0.5, ys + 0.5], axis=-1).reshape(-1, 2)


def inside(tri_px: np.ndarray, points: np.ndarray, eps: float = 0.0) -> np.ndarray:
    """True where all barycentric weights exceed ``eps`` (eps > 0 keeps away from edges)."""
    return (barycentric(tri_px, points) > eps).all(axis=1)


def edge_distance(tri_px: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Distance in pixels from each point to the nearest of the triangle's three edge lines."""
    d = np.full(len(points), np.inf)
    for i in range(3):
        p, q = tri_px[i], tri_px[(i + 1) % 3]
        n = np.array([q[1] - p[1], p[0] - q[0]])
        d = np.minimum(d, np.abs((points - p) @ n) / np.linalg.norm(n))
    return d


def triangle_area(tri_px: np.ndarray) -> float:
    a, b, c = tri_px
    return 0.5 * abs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))


def one_line_refusal(code: int, err: str, *needles: str) -> str:
    """The project's rule for bad input: exit 2 and exactly one line on stderr, no traceback; each needle in it."""
    lines = err.splitlines()
    assert code == 2 and len(lines) == 1 and "Traceback" not in err, f"exit {code}:\n{err}"
    for needle in needles:
        assert needle in lines[0], lines[0]
    return lines[0]


def render_both_paths(ctx, folder, size: tuple[int, int]) -> np.ndarray:
    """``folder``/scene.toml drawn by both paths at ``size`` (the fragment post path): asserts they agree exactly
    (one run, one machine) and gives the RGB as float64."""
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.wgpu_path.scene import render_scene_file

    path = folder / "scene.toml"
    wgpu = render_scene_file(path, size=size, ctx=ctx, frames=1, knobs={"post_path": "fragment"}).pixels
    raw = render_scene_reference(path, size=size)
    assert np.array_equal(wgpu, raw), "wgpu and raw differ"
    return wgpu[..., :3].astype(np.float64)


def same_mesh(a, b) -> None:
    """Two loaded meshes (core/models/mesh.Mesh) are equal field by field: arrays of one dtype, shape and value."""
    from dataclasses import fields

    for f in fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
            assert x is not None and y is not None, f.name
            assert x.dtype == y.dtype and x.shape == y.shape and np.array_equal(x, y), f.name
        else:
            assert x == y, f.name


def benchmark_script(name: str):
    """benchmarks/<name>.py imported as a module (the folder is no package), for tests of a probe's helpers."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "benchmarks" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
