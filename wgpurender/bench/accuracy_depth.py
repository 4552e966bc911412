"""The depth-stress scene: the depth knob where it matters, with an analytic ground truth.

In the final scene (near 0.1, far 50, surfaces metres apart) every depth setup gives nearly the same image.
This scene is tests/numerics/depth_planes.py's case written as a scene file, so it goes through the real scene
renderer and the same knob code: camera at the origin looking down -z, near 0.01, far 1e5, two unlit
camera-filling quads at 1e4 (red) and 1e4 * 1.0005 (green), the farther one drawn FIRST. With the standard
mapping both store depth ~1 - 1e-6, 5e-10 apart, below one step of depth24plus or of float32 near 1, so the
far quad keeps every pixel; reverse-Z stores ~1e-6 where float32 resolves a 5e-4 relative gap.

Ground truth, analytic: every pixel is the near quad's colour, linear (1, 0, 0) -> sRGB (255, 0, 0).
Wrong pixels are counted with :func:`wrong_pixels` (green shows; the hard-case test counts with it too).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

NEAR, FAR = 0.01, 1e5
DISTANCE, GAP = 1e4, 0.0005
FOV_Y = 60.0
NEAR_RGB8 = (255, 0, 0, 255)


def wrong_pixels(image: np.ndarray) -> int:
    """Pixels showing the farther (green) plane instead of the nearer (red) one."""
    return int(((image[..., 1] > 127) & (image[..., 0] < 128)).sum())

QUAD_OBJ = """# a unit quad in the xy plane facing +z (two counter-clockwise triangles)
v -1 -1 0
v 1 -1 0
v 1 1 0
v -1 1 0
f 1 2 3
f 1 3 4
"""

SCENE_TOML = """# written by wgpurender bench accuracy (wgpurender/bench/accuracy_depth.py): the depth-stress scene
description = "two camera-filling quads 0.05% apart at 1e4, near {near}, far {far}; the far one is drawn first"

[camera]
eye = [0.0, 0.0, 0.0]
target = [0.0, 0.0, -1.0]
fov_y = {fov}
near = {near}
far = {far}

[materials.near]
albedo_color = [1.0, 0.0, 0.0]
unlit = true

[materials.far]
albedo_color = [0.0, 1.0, 0.0]
unlit = true

[[models]]  # drawn first: with equal stored depths it keeps every pixel (compare "less" / "greater" fail)
path = "quad.obj"
material = "far"
transform = {{ translate = [0.0, 0.0, {far_z}], scale = {half} }}

[[models]]
path = "quad.obj"
material = "near"
transform = {{ translate = [0.0, 0.0, {near_z}], scale = {half} }}

[render]
size = [{w}, {h}]
msaa = 1
hdr = false
clear_color = [0.0, 0.0, 1.0, 1.0]
output_format = "rgba8unorm-srgb"
"""


def write_depth_scene(folder: str | Path, size: tuple[int, int]) -> Path:
    """Write depth_stress.toml and quad.obj into ``folder``; returns the scene file's path."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "quad.obj").write_text(QUAD_OBJ)
    # Half-size |z| * 2 covers the frustum: half-height tan(30 deg) |z| = 0.58 |z|, half-width 0.58 |z| * aspect.
    aspect = size[0] / size[1]
    half = 2.0 * DISTANCE * (1 + GAP) * max(1.0, aspect)
    text = SCENE_TOML.format(near=NEAR, far=FAR, fov=FOV_Y, far_z=-DISTANCE * (1 + GAP), near_z=-DISTANCE,
                             half=half, w=size[0], h=size[1])
    path = folder / "depth_stress.toml"
    path.write_text(text)
    return path


def analytic_image(size: tuple[int, int]) -> np.ndarray:
    """The exact image: the near quad everywhere."""
    return np.broadcast_to(np.array(NEAR_RGB8, dtype=np.uint8), (size[1], size[0], 4)).copy()
