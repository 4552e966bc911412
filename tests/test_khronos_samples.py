"""Khronos glTF sample models (tests/data/khronos, CC0, each with its README and source), drawn on both paths and
judged by the samples' own description: expectations come from the file's numbers, decoded here with numpy from its
base64 buffer (independent of the loader), and the camera.
"""

from __future__ import annotations

import base64
import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from test_gltf_render import PATHS, render

DATA = Path(__file__).parent / "data" / "khronos"
SIZE = (160, 160)


def file_floats(gltf: dict, accessor: int) -> np.ndarray:
    """A float VEC3 accessor of an embedded .gltf, read straight from its data: URI (byteStride honoured)."""
    acc = gltf["accessors"][accessor]
    view = gltf["bufferViews"][acc["bufferView"]]
    data = base64.b64decode(gltf["buffers"][view["buffer"]]["uri"].split(",", 1)[1])
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = view.get("byteStride", 12)
    return np.array([np.frombuffer(data, "<f4", 3, start + i * stride) for i in range(acc["count"])], np.float64)


def pixel(x: float, y: float, eye: tuple[float, float, float]) -> tuple[int, int]:
    """(column, row) of (x, y, 0) seen from ``eye`` looking down -z, fov_y 90, square image."""
    d = eye[2]
    ndc_x, ndc_y = (x - eye[0]) / d, (y - eye[1]) / d
    return int((ndc_x + 1) / 2 * SIZE[0]), int((1 - ndc_y) / 2 * SIZE[1])


def lit(image, x, y, eye, radius=1) -> bool:
    col, row = pixel(x, y, eye)
    return bool(image[row - radius: row + radius + 1, col - radius: col + radius + 1, :3].max() > 10)


def scene_for(tmp_path, sample: str, eye) -> Path:
    shutil.copy(DATA / sample / f"{sample}.gltf", tmp_path)
    target = [eye[0], eye[1], 0]
    path = tmp_path / "scene.toml"
    path.write_text(f"[camera]\neye = {list(eye)}\ntarget = {target}\nfov_y = 90\nnear = 0.1\nfar = 20\n\n"
                    f"[render]\nsize = [{SIZE[0]}, {SIZE[1]}]\nmsaa = 1\nhdr = false\nclear_color = [0, 0, 0, 1]\n\n"
                    f'[[models]]\npath = "{sample}.gltf"\n')
    return path


@pytest.mark.parametrize("which", PATHS)
def test_mesh_primitive_modes(ctx, tmp_path, which):
    """MeshPrimitiveModes: the seven hexagon vertices as points; the six spokes of LINES; the rim of LINE_LOOP
    with its closing segment (vertex 6 back to the centre, 0) and LINE_STRIP without it; three filled hexagons.
    Segments the indices never name (e.g. the rim edge 1-2 for LINES, 6-1 for the loop) stay black."""
    gltf = json.loads((DATA / "MeshPrimitiveModes" / "MeshPrimitiveModes.gltf").read_text())
    v = file_floats(gltf, 7)[:, :2]
    at = {node["mesh"]: np.array(node["translation"][:2], np.float64) for node in gltf["nodes"]}
    eye = (0.0, 0.0, 6.0)
    image = render(ctx, scene_for(tmp_path, "MeshPrimitiveModes", eye), which, size=SIZE)

    def seg(mesh, a, b):
        return at[mesh] + (v[a] + v[b]) / 2

    for k in range(7):
        assert lit(image, *(at[0] + v[k]), eye), (which, "point", k)
    for k in range(1, 7):
        assert lit(image, *seg(1, 0, k), eye), (which, "LINES spoke", k)
    assert not lit(image, *seg(1, 1, 2), eye, radius=0), (which, "LINES has no rim")
    for mesh in (2, 3):
        for k in range(6):
            assert lit(image, *seg(mesh, k, k + 1), eye), (which, mesh, "segment", k)
        assert not lit(image, *seg(mesh, 6, 1), eye, radius=0), (which, mesh, "segment 6-1 is not in the indices")
    assert lit(image, *seg(2, 6, 0), eye), (which, "LINE_LOOP closes 6 -> 0")
    assert not lit(image, *seg(3, 6, 0), eye, radius=0), (which, "LINE_STRIP stays open")
    for mesh in (4, 5, 6):
        for dx, dy in ((0.3, 0.3), (-0.4, -0.2), (0.5, -0.3), (-0.6, 0.1)):
            assert lit(image, *(at[mesh] + (dx, dy)), eye, radius=0), (which, "filled", mesh, dx, dy)
        assert not lit(image, *(at[mesh] + (1.0, 0.0)), eye, radius=0), (which, "outside", mesh)


@pytest.mark.parametrize("which", PATHS)
def test_simple_morph_default_weights(ctx, tmp_path, which):
    """SimpleMorph: the triangle at base + 0.5 target0 + 0.5 target1 (mesh.weights): points 15% inside each
    morphed corner are covered, points 25% beyond each are not (the apex moves from (0.5, 0.5) to (0.5, 1): the
    base pose would leave the point inside the morphed apex bare)."""
    gltf = json.loads((DATA / "SimpleMorph" / "SimpleMorph.gltf").read_text())
    base, t0, t1 = (file_floats(gltf, a)[:, :2] for a in (1, 2, 3))
    w = gltf["meshes"][0]["weights"]
    morphed = base + w[0] * t0 + w[1] * t1
    centre = morphed.mean(axis=0)
    eye = (float(centre[0]), float(centre[1]), 2.0)
    image = render(ctx, scene_for(tmp_path, "SimpleMorph", eye), which, size=SIZE)
    assert lit(image, *centre, eye, radius=0)
    for corner in morphed:
        assert lit(image, *(corner + 0.15 * (centre - corner)), eye, radius=0), (which, corner.tolist())
        assert not lit(image, *(corner - 0.25 * (centre - corner)), eye, radius=0), (which, corner.tolist())
    # the check can fail: the point inside the moved corner lies outside the base pose's triangle
    apex = int(np.argmax(np.linalg.norm(morphed - base, axis=1)))
    probe = morphed[apex] + 0.15 * (centre - morphed[apex])
    assert not inside_triangle(probe, base), "the sample's weights must move a corner out of the base pose"


def inside_triangle(p, tri) -> bool:
    (ax, ay), (bx, by), (cx, cy) = tri
    d = (by - cy) * (ax - cx) + (cx - bx) * (ay - cy)
    a = ((by - cy) * (p[0] - cx) + (cx - bx) * (p[1] - cy)) / d
    b = ((cy - ay) * (p[0] - cx) + (ax - cx) * (p[1] - cy)) / d
    return min(a, b, 1 - a - b) >= 0
