"""Procedural meshes and textures: the project's own assets (assets/make_assets.py) and test geometry.

Meshes are returned as plain arrays (positions, normals, uvs, indices) in the Mesh conventions of mesh.py:
counter-clockwise front faces seen from outside, outward unit normals, uv with v = 0 at the TOP of the image,
mapped so the image reads unmirrored from the front (generated tangents then have w = +1).

Textures are tileable (they wrap at their borders) and deterministic for a given seed. Normal maps are
tangent-space, +Y up (OpenGL / glTF convention), linear (not sRGB), encoded as ``rgb = n * 0.5 + 0.5``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass
class MeshArrays:
    """Vertex arrays of a procedural mesh (float64, Mesh conventions) and (F, 3) int64 triangle indices."""

    positions: np.ndarray
    normals: np.ndarray
    uvs: np.ndarray
    indices: np.ndarray


def grid_indices(rows: int, cols: int) -> np.ndarray:
    """Two CCW triangles per cell of a (rows+1) x (cols+1) vertex grid stored row-major.

    Vertex (i, j) is row i, column j. CCW assumes column index grows along +u (right) and row index along +v
    (down the image), seen from the front.
    """
    i, j = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    a = (i * (cols + 1) + j).ravel()
    b, c, d = a + 1, a + cols + 2, a + cols + 1  # right, below-right, below
    return np.concatenate([np.stack([a, d, c], 1), np.stack([a, c, b], 1)]).astype(np.int64)


def plane(width: float = 2.0, height: float = 2.0, cols: int = 1, rows: int = 1) -> MeshArrays:
    """A plane in z = 0 facing +Z, centred at the origin; u runs along +X, v = 0 at the top edge (+Y)."""
    u, v = np.meshgrid(np.linspace(0, 1, cols + 1), np.linspace(0, 1, rows + 1))
    positions = np.stack([(u - 0.5) * width, (0.5 - v) * height, np.zeros_like(u)], -1).reshape(-1, 3)
    normals = np.tile([0.0, 0.0, 1.0], (len(positions), 1))
    return MeshArrays(positions, normals, np.stack([u, v], -1).reshape(-1, 2), grid_indices(rows, cols))


def mirrored_quad(width: float = 2.0, height: float = 1.0, split_seam: bool = True) -> MeshArrays:
    """A quad facing +Z whose left half uses mirrored u: u goes 1 -> 0 across the left half and 0 -> 1 across the
    right half, so both halves show the same texture, mirrored about x = 0, and share one normal map.

    Left-half triangles have UV handedness -1, right-half +1. With ``split_seam`` the seam vertices (x = 0) are
    duplicated, one copy per half (what an exporter would write); without, they are shared (6 vertices).
    """
    xs = np.array([-0.5, 0.0, 0.5]) * width
    us = np.array([1.0, 0.0, 1.0])
    ys = np.array([0.5, -0.5]) * height
    vs = np.array([0.0, 1.0])
    pos = np.array([[x, y, 0.0] for y in ys for x in xs])
    uv = np.array([[u, v] for v in vs for u in us])
    # vertices: 0 1 2 (top row: left, seam, right), 3 4 5 (bottom row); left half = 0 1 4 3, right = 1 2 5 4
    left = [[0, 3, 4], [0, 4, 1]]
    right = [[1, 4, 5], [1, 5, 2]]
    indices = np.array(left + right, np.int64)
    if split_seam:
        pos, uv = np.concatenate([pos, pos[[1, 4]]]), np.concatenate([uv, uv[[1, 4]]])
        right_half = indices[2:]  # a view: edits land in indices
        right_half[right_half == 1] = 6
        right_half[right_half == 4] = 7
    return MeshArrays(pos, np.tile([0.0, 0.0, 1.0], (len(pos), 1)), uv, indices)


def torus(major: float = 1.0, minor: float = 0.4, segments: int = 96, rings: int = 48,
          u_repeat: float = 5.0, v_repeat: float = 2.0) -> MeshArrays:
    """A torus around +Y. u follows the major circle, v the tube (v = 0 on the outer equator, going down first).

    The seam rows/columns are duplicated so UVs are continuous within each copy. Returned uvs span
    [0, u_repeat] x [0, v_repeat] for a repeating sampler. Analytic normals; tangent = dP/du direction.
    """
    a = np.linspace(0.0, 2 * np.pi, segments + 1)  # around the major circle
    b = np.linspace(0.0, 2 * np.pi, rings + 1)  # around the tube
    bb, aa = np.meshgrid(b, a, indexing="ij")  # rows follow v (tube), columns follow u (major)
    # seen from outside, u grows to the right (clockwise seen from +Y, toward -Z first at +X) and v grows
    # downwards from the outer equator: the texture reads unmirrored, v = 0 at the top of the image
    ring = major + minor * np.cos(bb)
    positions = np.stack([ring * np.cos(aa), -minor * np.sin(bb), -ring * np.sin(aa)], -1)
    normals = np.stack([np.cos(bb) * np.cos(aa), -np.sin(bb), -np.cos(bb) * np.sin(aa)], -1)
    uvs = np.stack([aa / (2 * np.pi) * u_repeat, bb / (2 * np.pi) * v_repeat], -1)
    return MeshArrays(positions.reshape(-1, 3), normals.reshape(-1, 3), uvs.reshape(-1, 2),
                      grid_indices(rings, segments))


def torus_tangent(mesh: MeshArrays, major: float = 1.0) -> np.ndarray:
    """Analytic unit dP/du of :func:`torus` (the direction of growing major angle) for each vertex."""
    p = mesh.positions
    t = np.stack([p[:, 2], np.zeros(len(p)), -p[:, 0]], -1)  # d/da (r cos a, y, -r sin a) = (z, 0, -x)
    return t / np.linalg.norm(t, axis=1, keepdims=True)


def box(size: float = 1.0) -> MeshArrays:
    """A cube centred at the origin, 4 vertices per face (24), each face mapped to the whole [0,1]^2 texture,
    upright and unmirrored seen from outside (the top face reads with its top toward -Z, the bottom toward +Z)."""
    h = size / 2
    faces = [  # (normal, right, up) of each face seen from outside
        ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
        ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
        ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
        ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
        ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
        ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
    ]
    corner_uv = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])  # top-left, top-right, bottom-right, ..
    pos, nrm, uv, idx = [], [], [], []
    for k, (n, r, u) in enumerate(faces):
        n, r, u = np.array(n, float), np.array(r, float), np.array(u, float)
        for cu, cv in corner_uv:
            pos.append(h * (n + (2 * cu - 1) * r + (1 - 2 * cv) * u))
            nrm.append(n)
            uv.append((cu, cv))
        base = 4 * k
        idx += [[base, base + 3, base + 2], [base, base + 2, base + 1]]
    return MeshArrays(np.array(pos), np.array(nrm), np.array(uv), np.array(idx, np.int64))


# ---------------------------------------------------------------- textures


def _tileable_noise(rng: np.random.Generator, size: int, cells: int) -> np.ndarray:
    """Value noise in [0, 1]: random values on a cells x cells lattice, smoothly interpolated, wrapping."""
    lattice = rng.random((cells, cells))
    x = np.arange(size) * cells / size
    i0 = np.floor(x).astype(int)
    f = x - i0
    f = f * f * (3 - 2 * f)
    i1 = (i0 + 1) % cells
    rows = lattice[i0] * (1 - f)[:, None] + lattice[i1] * f[:, None]
    return rows[:, i0] * (1 - f)[None, :] + rows[:, i1] * f[None, :]


def fractal_noise(rng: np.random.Generator, size: int, base_cells: int = 4, octaves: int = 4) -> np.ndarray:
    """Sum of value-noise octaves (halving amplitude, doubling frequency), normalised to [0, 1], tileable."""
    total = sum(0.5**o * _tileable_noise(rng, size, base_cells * 2**o) for o in range(octaves))
    return (total - total.min()) / (total.max() - total.min())


@dataclass
class BrickMaps:
    """Brick material maps, (H, W) or (H, W, 3) float64 in [0, 1]; albedo is linear (encode to sRGB to save)."""

    height: np.ndarray
    albedo: np.ndarray
    roughness: np.ndarray
    mortar: np.ndarray  # 1 in the mortar joints, 0 on bricks (soft edge)


def brick_maps(size: int = 512, rows: int = 8, cols: int = 4, mortar: float = 0.035, bevel: float = 0.03,
               seed: int = 7) -> BrickMaps:
    """Running-bond bricks (alternate rows offset by half a brick), tileable: rows x cols bricks per tile.

    Heights: brick faces at ~1 with noise and rounded (bevelled) edges, mortar at 0.15 with its own grain.
    mortar and bevel are fractions of the texture width.
    """
    rng = np.random.default_rng(seed)
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    row = np.floor(y * rows).astype(int)
    xs = x * cols + 0.5 * (row % 2)
    col = np.floor(xs).astype(int) % cols
    # distance (in texture-width units) from the brick edges
    dx = np.minimum(xs - np.floor(xs), np.ceil(xs) - xs) / cols
    fy = y * rows
    dy = np.minimum(fy - np.floor(fy), np.ceil(fy) - fy) / rows
    edge = np.minimum(dx, dy) - mortar / 2
    profile = np.clip(edge / bevel, 0.0, 1.0)
    profile = np.sin(profile * np.pi / 2)  # rounded bevel
    brick_id = row * cols + col
    brick_tone = rng.random(rows * cols)[brick_id]
    grain = fractal_noise(rng, size, 8, 4)
    pits = fractal_noise(rng, size, 32, 2)
    height = 0.15 + 0.1 * grain * (1 - profile) + profile * (0.8 + 0.1 * grain - 0.12 * (pits > 0.75))
    mortar_mask = 1.0 - np.clip(edge / 0.004 + 0.5, 0.0, 1.0)
    brick_rgb = np.array([0.42, 0.13, 0.07]) * (0.7 + 0.6 * brick_tone)[..., None]
    brick_rgb = brick_rgb * (0.85 + 0.3 * grain)[..., None]
    mortar_rgb = np.array([0.45, 0.43, 0.40]) * (0.8 + 0.3 * grain)[..., None]
    albedo = np.clip(brick_rgb * (1 - mortar_mask[..., None]) + mortar_rgb * mortar_mask[..., None], 0, 1)
    roughness = np.clip(0.55 + 0.3 * mortar_mask + 0.15 * (grain - 0.5), 0.0, 1.0)
    return BrickMaps(height, albedo, roughness, mortar_mask)


def dome_height(size: int = 256, domes: int = 2) -> np.ndarray:
    """domes x domes hemispherical bumps on a flat field, tileable; height 1 at each dome's top, 0 outside."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size * domes
    r = np.hypot(x - np.floor(x) - 0.5, y - np.floor(y) - 0.5) / 0.4
    return np.sqrt(np.clip(1.0 - r * r, 0.0, 1.0))


def normals_from_height(height: np.ndarray, strength: float) -> np.ndarray:
    """Tangent-space unit normals (H, W, 3) of a height field, +Y up (OpenGL / glTF convention).

    ``n = normalize(-strength * dh/dx, +strength * dh/drow, 1)`` with central differences in texels,
    wrapping at the borders; x grows to the right (+u), rows grow downwards, which is -Y of the normal map, hence
    the sign of the second term. strength = relief height in texels for a height step of 1.
    """
    h = np.asarray(height, np.float64)
    dh_dx = (np.roll(h, -1, axis=1) - np.roll(h, 1, axis=1)) / 2
    dh_drow = (np.roll(h, -1, axis=0) - np.roll(h, 1, axis=0)) / 2
    n = np.stack([-strength * dh_dx, strength * dh_drow, np.ones_like(h)], -1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def encode_normal_map(normals: np.ndarray) -> np.ndarray:
    """Unit normals -> (H, W, 3) uint8 with rgb = n * 0.5 + 0.5 (linear data, never sRGB-encode)."""
    return np.round((np.asarray(normals) * 0.5 + 0.5) * 255.0).astype(np.uint8)


def decode_normal_map(pixels: np.ndarray) -> np.ndarray:
    """(H, W, 3|4) uint8 -> unit normals, the inverse of :func:`encode_normal_map` up to quantisation."""
    n = np.asarray(pixels[..., :3], np.float64) / 255.0 * 2.0 - 1.0
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def write_obj(path: str | os.PathLike, mesh: MeshArrays, mtl_name: str | None = None,
              material: str = "material") -> Path:
    """Write an OBJ (v, vt, vn, f v/vt/vn). vt is written in OBJ's convention (v = 0 at the bottom): 1 - v."""
    path = Path(path)
    lines = ["# generated by wgpurender assets/make_assets.py"]
    if mtl_name:
        lines += [f"mtllib {mtl_name}", f"usemtl {material}"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in mesh.positions]
    lines += [f"vt {u:.6f} {1.0 - v:.6f}" for u, v in mesh.uvs]
    lines += [f"vn {x:.6f} {y:.6f} {z:.6f}" for x, y, z in mesh.normals]
    lines += ["f " + " ".join(f"{i}/{i}/{i}" for i in tri + 1) for tri in mesh.indices]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path
