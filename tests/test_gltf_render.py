"""glTF files render as their authors meant, on both paths (wgpu and raw Vulkan), checked against the file.

Every model is generated here (tests/gltf_gen.py) and every expectation is computed from the numbers written into
it: where a vertex lands (gltf_gen.pixel_of: the camera at z = 2, fov 90), which colour a corner has. The two
paths share the loader, so agreeing with each other proves nothing about it: each is checked against the file.
"""

from __future__ import annotations

import numpy as np
import pytest
from gltf_gen import GltfWriter, pixel_of, scene_text

from wgpurender.core.imageio import to_uint8

SIZE = (96, 96)
PATHS = ("wgpu", "raw")


def render(ctx, path, which: str, size=SIZE) -> np.ndarray:
    """The (H, W, 4) uint8 image of a scene file on one path (sRGB-encoded output)."""
    if which == "wgpu":
        from wgpurender.wgpu_path.scene_render import render_scene_file

        pixels = render_scene_file(path, size=size, ctx=ctx, frames=1, knobs={"post_path": "fragment"}).pixels
    else:
        from wgpurender.raw_path.scene import render_scene_reference

        pixels = render_scene_reference(path, size=size)
    return to_uint8(pixels) if pixels.dtype != np.uint8 else pixels


def write_scene(tmp_path, model: str, material: str | None = None, extra: str = "", size=SIZE):
    path = tmp_path / "scene.toml"
    path.write_text(scene_text(model, size, material, extra))
    return path


# -- sparse positions -------------------------------------------------------------------------------------------

SPARSE_X = np.float32([-1.5, -0.5, 0.5, 1.5])
SPARSE_TOP = np.float32([0.3, 0.8, 1.3])  # the sparse block's heights for top vertices 5, 6, 7


def _sparse_strip(tmp_path):
    """Bottom row y = -1.5, top row y = 0 in the base data; the sparse block lifts top vertices 5, 6, 7."""
    base = np.array([[x, -1.5, 0] for x in SPARSE_X] + [[x, 0, 0] for x in SPARSE_X], np.float32)
    changed = np.array([5, 6, 7], np.uint8)
    values = base[changed].copy()
    values[:, 1] = SPARSE_TOP
    g = GltfWriter()
    faces = np.array([[k, k + 1, k + 5, k, k + 5, k + 4] for k in range(3)], np.uint16).ravel()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(base, sparse=(changed, values))},
                         "indices": g.accessor(faces)}]))
    return g.write(tmp_path / "sparse.glb")


@pytest.mark.parametrize("which", PATHS)
def test_sparse_positions_render_displaced(ctx, tmp_path, which):
    """The top edge passes through each lifted vertex: at the vertex's column (one pixel inside the strip) the
    highest covered row is where the camera puts (x, height) of the file's sparse values, within 1.5 pixels.
    Without the sparse block all three would sit at y = 0."""
    _sparse_strip(tmp_path)
    image = render(ctx, write_scene(tmp_path, "sparse.glb", "{ unlit = true }"), which)
    covered = image[..., :3].max(axis=2) > 128
    for x, height in zip(SPARSE_X[1:], SPARSE_TOP, strict=True):
        column, row = pixel_of(float(x), float(height), SIZE)
        col = int(min(column, SIZE[0] - 1.5)) - (1 if x == SPARSE_X[-1] else 0)
        top = int(np.argmax(covered[:, col]))
        assert covered[:, col].any() and abs(top + 0.5 - row) <= 1.5, (which, x, height, top, row)
