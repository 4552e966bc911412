"""Course step 5: the generated texture, the ground plane it lies on, and the samplers that read it.

Left half of the image: the whole plane through one combined texture + sampler.
Right half: the plane cut into four lanes along its length, one texture and a
sampler per lane (:data:`SEPARATE_SAMPLERS`, left to right).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from wgpurender.core.course.samplers import BILINEAR, NEAREST, TRILINEAR, SamplerSpec, anisotropic
from wgpurender.core.view.transforms import look_at, perspective

BACKGROUND = (0.02, 0.03, 0.06, 1.0)
VERTEX_FLOATS = 5  # vec3 position, vec2 uv

# The ground plane: y = 0, x in [-2, 2], z from 3 (near, below the view) to -60 (far); the texture
# repeats every 2 units both ways, so texels stay square on the plane. On the right
# it is cut into 4 lanes along x with LANE_GAP units of background between them.
PLANE_X = (-2.0, 2.0)
PLANE_Z = (3.0, -60.0)
TILE = 2.0
LANE_GAP = 0.1
EYE, LOOK_AT = (0.0, 0.8, 3.5), (0.0, 0.0, -8.0)
FOV_Y = 50.0
NEAR, FAR = 0.05, 100.0
SCROLL_PER_SECOND = 0.25  # texture repeats per second along the plane

COMBINED_SAMPLER = SamplerSpec(max_anisotropy=16, address_mode_u="mirror-repeat", address_mode_v="mirror-repeat")
SEPARATE_SAMPLERS: tuple[tuple[str, SamplerSpec], ...] = (
    ("nearest, no mips", dataclasses.replace(NEAREST, lod_max_clamp=0.0)),
    ("bilinear, no mips", dataclasses.replace(BILINEAR, lod_max_clamp=0.0)),
    ("trilinear", TRILINEAR),
    ("trilinear + 16x anisotropic", anisotropic(16)),
)


def pattern_pixels(size: int = 256, cells: int = 8) -> np.ndarray:
    """The generated colour texture (sRGB bytes): a checker of white and a colour gradient, with dark grid lines.

    Thin lines and sharp edges are what filtering changes most visibly.
    """
    y, x = np.mgrid[0:size, 0:size].astype(np.float64) / (size - 1)
    cell = size // cells
    iy, ix = np.mgrid[0:size, 0:size]
    dark = ((ix // cell) + (iy // cell)) % 2 == 1
    rgb = np.empty((size, size, 3))
    rgb[..., 0] = 0.15 + 0.8 * x
    rgb[..., 1] = 0.25 + 0.6 * y
    rgb[..., 2] = 0.85 - 0.6 * x
    rgb[~dark] = 0.95
    line = ((ix % cell) < 2) | ((iy % cell) < 2)
    rgb[line] = 0.05
    pixels = np.empty((size, size, 4), dtype=np.uint8)
    pixels[..., :3] = np.round(rgb * 255)
    pixels[..., 3] = 255
    return pixels


def quad_vertices(corners: np.ndarray, uv_rect=(0.0, 0.0, 1.0, 1.0)) -> np.ndarray:
    """Two triangles from 4 corners (top-left, top-right, bottom-left, bottom-right) as (6, 5) float32.

    uv (u0, v0) goes to the top-left corner and (u1, v1) to the bottom-right.
    """
    u0, v0, u1, v1 = uv_rect
    uvs = np.array([[u0, v0], [u1, v0], [u0, v1], [u1, v1]])
    verts = np.hstack([np.asarray(corners, dtype=np.float64), uvs])
    return verts[[0, 2, 1, 1, 2, 3]].astype(np.float32)


# A screen-aligned quad filling NDC, uv (0,0) at the top-left pixel: with an identity mvp one texel
# of an n-texel texture covers exactly size/n pixels.
SCREEN_QUAD = quad_vertices(np.array([[-1, 1, 0], [1, 1, 0], [-1, -1, 0], [1, -1, 0]]))


def plane_vertices(x_range=PLANE_X) -> np.ndarray:
    """The plane (or a lane of it) between x_range; uv follow world x and z, so lanes continue the pattern."""
    x0, x1 = x_range
    z0, z1 = PLANE_Z
    corners = np.array([[x0, 0, z1], [x1, 0, z1], [x0, 0, z0], [x1, 0, z0]])  # far edge at the top
    u0 = (x0 - PLANE_X[0]) / TILE
    return quad_vertices(corners, (u0, 0.0, u0 + (x1 - x0) / TILE, (z0 - z1) / TILE))


def lane_ranges(count: int, gap: float = LANE_GAP) -> list[tuple[float, float]]:
    """x ranges of ``count`` equal lanes across the plane, ``gap`` apart."""
    x0, x1 = PLANE_X
    width = (x1 - x0) / count
    ranges = []
    for i in range(count):
        left = x0 + i * width + (gap / 2 if i > 0 else 0.0)
        right = x0 + (i + 1) * width - (gap / 2 if i < count - 1 else 0.0)
        ranges.append((left, right))
    return ranges


def stage_vertices() -> np.ndarray:
    """The stage's vertex buffer: vertices 0..5 the whole plane (left half), then 6 per lane (right half)."""
    lanes = [plane_vertices(r) for r in lane_ranges(len(SEPARATE_SAMPLERS))]
    return np.concatenate([plane_vertices(), *lanes])


def plane_mvp(aspect: float) -> np.ndarray:
    return perspective(FOV_Y, aspect, NEAR, FAR) @ look_at(EYE, LOOK_AT)


def uv_offset(t: float) -> tuple[float, float]:
    """The texture scroll at time ``t``."""
    return (0.0, -SCROLL_PER_SECOND * t)


def halves(width: int) -> tuple[tuple[int, int], tuple[int, int]]:
    """(x, width) of the left and right viewports: the left one gets width // 2 columns."""
    left = width // 2
    return (0, left), (left, width - left)
