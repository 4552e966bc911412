"""A scene's meshes share one vertex and one index buffer (wgpu_path/scene/resources.py, upload_meshes): each draw
binds its own mesh at its offset. Built here: a one-triangle mesh (16-bit indices, 6 bytes: padded), a plane of
66,049 vertices (32-bit indices) and a cube, side by side, unlit in three colours; each colour must be where the
camera projects its model (the scene's own numbers), and the three meshes must sit in one buffer pair."""

from __future__ import annotations

import numpy as np

from wgpurender.core.models import procedural
from wgpurender.core.scene import parse_scene

SIZE = (120, 48)
TRIANGLE = "v -0.8 -0.8 0\nv 0.8 -0.8 0\nv 0 0.8 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n"


def test_three_meshes_of_two_index_formats_draw_from_one_buffer_pair(ctx, tmp_path):
    from wgpurender.wgpu_path.scene import load_renderer
    from wgpurender.wgpu_path.scene.frame import render_frame

    (tmp_path / "tri.obj").write_text(TRIANGLE)
    procedural.write_obj(tmp_path / "plane.obj", procedural.plane(1.6, 1.6, cols=256, rows=256))
    procedural.write_obj(tmp_path / "cube.obj", procedural.box(1.2))
    places = {"tri.obj": (-3.0, (255, 0, 0)), "plane.obj": (0.0, (0, 0, 255)), "cube.obj": (3.0, (0, 255, 0))}
    body = "".join(f'[[models]]\npath = "{name}"\nmaterial = {{ albedo_color = [{r / 255}, {g / 255}, {b / 255}], '
                   f'unlit = true }}\ntransform = {{ translate = [{x}, 0, 0] }}\n\n'
                   for name, (x, (r, g, b)) in places.items())
    path = tmp_path / "s.toml"
    path.write_text("[camera]\neye = [0, 0, 9]\ntarget = [0, 0, 0]\nfov_y = 40\n\n" + body
                    + f"[render]\nsize = [{SIZE[0]}, {SIZE[1]}]\nmsaa = 1\nhdr = false\n")
    renderer = load_renderer(path, ctx)
    buffers = list(renderer.resources._buffers.values())
    assert len(buffers) == 3 and len({id(b.vertex) for b in buffers}) == 1 and len({id(b.index) for b in buffers}) == 1
    assert sorted(b.index_format for b in buffers) == ["uint16", "uint16", "uint32"]
    img, _ = render_frame(ctx, renderer, renderer.create_output())
    scene = parse_scene(path.read_text(), path)
    clip_from_world = scene.camera.projection(SIZE[0] / SIZE[1]) @ scene.camera.view()
    for name, (x, rgb) in places.items():
        c = clip_from_world @ np.array([x, 0.0, 0.0, 1.0])
        px = img[int((1 - c[1] / c[3]) / 2 * SIZE[1]), int((c[0] / c[3] + 1) / 2 * SIZE[0]), :3]
        assert px.tolist() == list(rgb), name
