"""The fuzz harness's classifier can tell each bad outcome (so a fuzz run with 0 of them means something)."""

from __future__ import annotations

import numpy as np
from harness import classify
from PIL import Image
from reliab_gen import scene_text, triangle_gltf, write_gltf


def _setup(tmp_path, eye="[0, 0, 3]"):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    scene = tmp_path / "scene.toml"
    scene.write_text(scene_text(camera=f"eye = {eye}\ntarget = [0, 0, 0]\nnear = 0.1\nfar = 20.0\n"))
    (tmp_path / "out").mkdir()
    return scene, tmp_path / "out" / "out.png"


def _png(path, pixels):
    Image.fromarray(pixels.astype(np.uint8)).save(path)


def test_uniform_image_of_a_visible_triangle_is_blank(tmp_path):
    scene, out = _setup(tmp_path)
    _png(out, np.full((30, 40, 4), 13))
    assert classify(0, "", out, scene) == "blank"
    pixels = np.full((30, 40, 4), 13)
    pixels[15, 20] = 255
    _png(out, pixels)
    assert classify(0, "", out, scene) == "render"


def test_a_triangle_seen_from_behind_is_culled_so_uniform_is_right(tmp_path):
    scene, out = _setup(tmp_path, eye="[0, 0, -3]")  # the triangle faces +z: from -z its back is culled
    _png(out, np.full((30, 40, 4), 13))
    assert classify(0, "", out, scene) == "render"


def test_errors_partial_files_and_extra_lines(tmp_path):
    scene, out = _setup(tmp_path)
    assert classify(2, "wgpurender render: error: x\n", out, scene) == "error"
    assert classify(2, "warning\nwgpurender render: error: x\n", out, scene) == "multiline"
    (out.parent / ".out.png.wgpurender-1.tmp").write_bytes(b"half")
    assert classify(2, "wgpurender render: error: x\n", out, scene) == "partial"
    (out.parent / ".out.png.wgpurender-1.tmp").unlink()
    out.write_bytes(b"\x89PNG\r\n\x1a\n truncated")
    assert classify(0, "", out, scene) == "partial"
    assert classify(1, "Traceback (most recent call last):\n", out, scene) == "traceback"
