"""The scene shading model written out once more, in float64 numpy, for the tests to check against.

Nothing here comes from the renderer: the constants are the course's documented values (scene.wgsl's
header, docs/scenes.md), typed in again, and the formulas are the documented ones. When the course
core (``wgpurender/core/course/``) publishes its scene constants, :func:`course_constant` reads them from
there, the one place both render paths are meant to take them from; until then it uses the value written
here. Either way a path that keeps its *own* differing copy of a constant fails the tests.

Also the pieces the scene tests share: a quad that exactly fills a 45-degree view, the world point
under every pixel centre, sRGB transfer functions, and rendering a scene text on both paths.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

# The course's values (scene.wgsl: "L = ambient * albedo + ...", "specular is the dielectric reflectance 0.04").
DOCUMENTED = {"AMBIENT": (0.03, 0.03, 0.035), "SPECULAR": 0.04}
FOV = 45.0


def course_constant(name: str):
    """The course core's value of a scene constant if the core has it, else the documented value."""
    import importlib

    try:
        course = importlib.import_module("wgpurender.core.course")  # the API-free course core (issue 11)
    except ImportError:
        return DOCUMENTED[name]
    for module_name in ("shading", "scene", "lighting", "materials", "constants"):
        try:
            module = importlib.import_module(f"wgpurender.core.course.{module_name}")
        except ImportError:
            continue
        if hasattr(module, name):
            return getattr(module, name)
    return getattr(course, name, DOCUMENTED[name])


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1), linear [0, 1] -> encoded [0, 1]."""
    x = np.clip(np.asarray(linear, np.float64), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1.0 / 2.4) - 0.055)


def srgb_decode(encoded: np.ndarray) -> np.ndarray:
    """Encoded [0, 1] -> linear [0, 1]."""
    c = np.asarray(encoded, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def shininess(roughness) -> np.ndarray:
    """The Beckmann-matched Blinn-Phong exponent s = clamp(2 / r^4 - 2, 1, 4096)."""
    r = np.clip(np.asarray(roughness, np.float64), 0.0, 1.0)
    return np.clip(2.0 / np.maximum(r**4, 1e-6) - 2.0, 1.0, 4096.0)


def normalize(v: np.ndarray) -> np.ndarray:
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def blinn_phong(n, to_light, v, albedo, roughness, irradiance=1.0) -> np.ndarray:
    """Normalized Blinn-Phong, per pixel, (..., 3): E * max(n.l, 0) * (albedo + F0 (s + 8) / 8 max(n.h, 0)^s)."""
    n, to_light, v = np.broadcast_arrays(normalize(n), normalize(to_light), normalize(v))
    n_dot_l = np.maximum(np.sum(n * to_light, axis=-1), 0.0)
    h = normalize(to_light + v)
    s = shininess(roughness)
    spec = course_constant("SPECULAR") * (s + 8.0) / 8.0 * np.maximum(np.sum(n * h, axis=-1), 0.0) ** s
    albedo = np.asarray(albedo, np.float64)
    return np.asarray(irradiance, np.float64) * n_dot_l[..., None] * (albedo + spec[..., None])


def view_distance() -> float:
    """Distance from the eye at which a quad of height 2 exactly fills a FOV-degree vertical view."""
    return 1.0 / np.tan(np.radians(FOV) / 2.0)


def pixel_points_on_plane(size: tuple[int, int], distance: float) -> np.ndarray:
    """World points (H, W, 3) in the plane z = 0 under each pixel centre, eye at (0, 0, distance) looking at -Z."""
    w, h = size
    ys, xs = np.mgrid[0:h, 0:w] + 0.5
    half_h = distance * np.tan(np.radians(FOV) / 2.0)
    return np.stack([(xs / w * 2 - 1) * half_h * w / h, (1 - ys / h * 2) * half_h, np.zeros_like(xs)], axis=-1)


def camera_toml(distance: float) -> str:
    return f"""
[camera]
eye = [0.0, 0.0, {float(distance)!r}]
target = [0.0, 0.0, 0.0]
fov_y = {FOV}
"""


def render_wgpu(ctx, text: str, folder: Path) -> np.ndarray:
    """Render a scene text on the wgpu path (paths in it relative to ``folder``): (H, W, 4) pixels."""
    from wgpurender.core.plan import resolve_plan
    from wgpurender.core.scene import parse_scene
    from wgpurender.wgpu_path.scene import SceneRenderer, render_frame

    scene = parse_scene(text, folder / "scene.toml")
    renderer = SceneRenderer(ctx, scene, resolve_plan(scene, None))
    target = renderer.create_output()
    return render_frame(ctx, renderer, target)[0]


def render_raw(text: str, folder: Path) -> np.ndarray:
    """The same on the raw-Vulkan path."""
    from wgpurender.raw_path.scene import render_scene_reference

    path = folder / "scene.toml"
    path.write_text(text, encoding="utf-8")
    return render_scene_reference(path)
