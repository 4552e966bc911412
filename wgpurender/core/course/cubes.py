"""Course step 4: the rotating cubes, their camera and their light.

Matrices are float64 (:mod:`wgpurender.core.view.transforms`); each path packs them its own way.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wgpurender.core.view import transforms as tf

BACKGROUND = (0.02, 0.02, 0.03, 1.0)
DEPTH_FORMAT = "depth32float"

# Lighting (world space): direction towards the light, and the ambient floor.
LIGHT_DIR = np.array([0.4, 0.9, 0.6]) / np.linalg.norm([0.4, 0.9, 0.6])
AMBIENT = 0.2

# One flat colour per face (linear RGB), by outward normal; every channel >= 0.2.
FACE_NORMALS = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
FACE_COLORS = np.array(
    [
        [0.90, 0.25, 0.20],  # +x red
        [0.20, 0.80, 0.85],  # -x cyan
        [0.30, 0.85, 0.25],  # +y green
        [0.85, 0.30, 0.80],  # -y magenta
        [0.25, 0.35, 0.90],  # +z blue
        [0.90, 0.85, 0.25],  # -z yellow
    ]
)
VERTEX_FLOATS = 9  # position, normal, colour: three vec3


def permute_channels(rgb: np.ndarray, object_index: int) -> np.ndarray:
    """The shaders' per-object channel order (rgb, gbr, brg), for references in numpy."""
    return np.asarray(rgb)[..., [(0, 1, 2), (1, 2, 0), (2, 0, 1)][object_index % 3]]


def cube_mesh() -> tuple[np.ndarray, np.ndarray]:
    """A cube of half-size 1: 24 vertices (position, normal, colour as float32) and 36 uint16 indices.

    Each face has its own 4 vertices so normal and colour are flat. Triangles wind
    counter-clockwise seen from outside (right-handed: u x v = n).
    """
    vertices, indices = [], []
    for n, color in zip(FACE_NORMALS, FACE_COLORS, strict=True):
        u = np.roll(n, 1)
        v = np.cross(n, u)
        base = len(vertices)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            vertices.append(np.concatenate([n + su * u + sv * v, n, color]))
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return np.array(vertices, dtype=np.float32), np.array(indices, dtype=np.uint16)


@dataclass(frozen=True)
class CubeSpec:
    """One cube: where it is, how it spins (``speed`` degrees per second about ``axis``), its tint."""

    position: tuple[float, float, float]
    axis: tuple[float, float, float] = (0.0, 1.0, 0.0)
    speed: float = 90.0
    phase: float = 0.0  # degrees at t = 0
    half_size: float = 0.6
    tint: tuple[float, float, float, float] = (1.0, 1.0, 1.0, 1.0)

    def world(self, t: float) -> np.ndarray:
        """float64 model matrix at time ``t`` (seconds): translate * rotate * scale."""
        angle = np.radians(self.phase + self.speed * t)
        return tf.translate(self.position) @ tf.rotate(self.axis, angle) @ tf.scale(self.half_size)


@dataclass(frozen=True)
class CameraSpec:
    eye: tuple[float, float, float] = (0.0, 2.5, 7.0)
    target: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    fov_y: float = 45.0
    near: float = 0.1
    far: float = 50.0

    def matrices(self, aspect: float) -> tuple[np.ndarray, np.ndarray]:
        """(proj, view), float64."""
        return tf.perspective(self.fov_y, aspect, self.near, self.far), tf.look_at(self.eye, self.target, self.up)


DEFAULT_CUBES = (
    CubeSpec((-2.1, 0.0, 0.0), axis=(0, 1, 0), speed=90.0, phase=30.0, half_size=0.6),
    CubeSpec((0.0, 0.0, 0.0), axis=(1, 1, 0), speed=60.0, phase=20.0, half_size=0.7, tint=(1.0, 0.85, 0.7, 1.0)),
    CubeSpec((2.1, 0.0, 0.0), axis=(0, 0, 1), speed=45.0, phase=-25.0, half_size=0.6, tint=(0.75, 0.9, 1.0, 1.0)),
)


def camera_values(camera: CameraSpec, aspect: float) -> dict:
    """The camera block's values for a frame: projection, view, light direction, ambient."""
    proj, view = camera.matrices(aspect)
    return {"proj": proj, "view": view, "light_dir": LIGHT_DIR, "ambient": AMBIENT}


def object_values(cubes, t: float) -> list[dict]:
    """Each cube's world matrix and normal matrix at time ``t``."""
    worlds = [cube.world(t) for cube in cubes]
    return [{"world": w, "normal": tf.normal_matrix(w)} for w in worlds]


def draw_values(cubes) -> list[dict]:
    """The per-draw push constants: each cube's tint and its index (which picks its channel order)."""
    return [{"tint": cube.tint, "object_index": k} for k, cube in enumerate(cubes)]
