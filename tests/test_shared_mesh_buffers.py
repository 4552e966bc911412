"""A scene's meshes share one vertex and one index buffer (wgpu_path/scene/resources.py, upload_meshes): each draw
binds its own mesh at its offset. Built here: a one-triangle mesh (16-bit indices, 6 bytes: padded), a plane of
66,049 vertices (32-bit indices) and a cube, side by side, unlit in three colours; each colour must be where the
camera projects its model (the scene's own numbers), and the three meshes must sit in one buffer pair."""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.models import procedural
from wgpurender.core.scene import parse_scene

SIZE = (120, 48)
TRIANGLE = "v -0.8 -0.8 0\nv 0.8 -0.8 0\nv 0 0.8 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n"


PLACES = {"tri.obj": (-3.0, (255, 0, 0)), "plane.obj": (0.0, (0, 0, 255)), "cube.obj": (3.0, (0, 255, 0))}


def _scene(tmp_path):
    (tmp_path / "tri.obj").write_text(TRIANGLE)
    procedural.write_obj(tmp_path / "plane.obj", procedural.plane(1.6, 1.6, cols=256, rows=256))
    procedural.write_obj(tmp_path / "cube.obj", procedural.box(1.2))
    body = "".join(f'[[models]]\npath = "{name}"\nmaterial = {{ albedo_color = [{r / 255}, {g / 255}, {b / 255}], '
                   f'unlit = true }}\ntransform = {{ translate = [{x}, 0, 0] }}\n\n'
                   for name, (x, (r, g, b)) in PLACES.items())
    path = tmp_path / "s.toml"
    path.write_text("[camera]\neye = [0, 0, 9]\ntarget = [0, 0, 0]\nfov_y = 40\n\n" + body
                    + f"[render]\nsize = [{SIZE[0]}, {SIZE[1]}]\nmsaa = 1\nhdr = false\n")
    return path


def _assert_each_colour_where_its_model_projects(ctx, renderer, path):
    from wgpurender.wgpu_path.scene.frame import render_frame

    img, _ = render_frame(ctx, renderer, renderer.create_output())
    scene = parse_scene(path.read_text(), path)
    clip_from_world = scene.camera.projection(SIZE[0] / SIZE[1]) @ scene.camera.view()
    for name, (x, rgb) in PLACES.items():
        c = clip_from_world @ np.array([x, 0.0, 0.0, 1.0])
        px = img[int((1 - c[1] / c[3]) / 2 * SIZE[1]), int((c[0] / c[3] + 1) / 2 * SIZE[0]), :3]
        assert px.tolist() == list(rgb), name


def test_three_meshes_of_two_index_formats_draw_from_one_buffer_pair(ctx, tmp_path):
    from wgpurender.wgpu_path.scene import load_renderer

    path = _scene(tmp_path)
    renderer = load_renderer(path, ctx)
    buffers = list(renderer.resources._buffers.values())
    assert len(buffers) == 3 and len({id(b.vertex) for b in buffers}) == 1 and len({id(b.index) for b in buffers}) == 1
    assert sorted(b.index_format for b in buffers) == ["uint16", "uint16", "uint32"]
    _assert_each_colour_where_its_model_projects(ctx, renderer, path)


def test_each_draw_holds_its_own_meshs_buffers_and_all_of_its_indices(ctx, tmp_path):
    """The draws' state (made from the upload's per-draw answer) names each draw's own mesh: the buffers its mesh
    key was placed in, no second upload, and as many indices as its file's triangles (from the meshes written)."""
    from wgpurender.wgpu_path.scene import load_renderer

    renderer = load_renderer(_scene(tmp_path), ctx)
    indices = {"tri.obj": 3, "plane.obj": procedural.plane(1.6, 1.6, cols=256, rows=256).indices.size,
               "cube.obj": procedural.box(1.2).indices.size}
    uploaded = len(renderer.resources._buffers)
    state = renderer.scene_pass.draw_state
    assert sorted(d.model_path.name for d, *_ in state) == sorted(indices)
    for draw, _, _, _, buffers, (first, count) in state:
        assert (first, count) == (0, indices[draw.model_path.name]) == (0, buffers.index_count), draw.label
        assert renderer.resources.mesh_buffers(draw) is buffers, draw.label
    assert len(renderer.resources._buffers) == uploaded == 3


def test_buffer_places_start_a_new_pair_where_the_limit_would_be_passed():
    from wgpurender.core.plan.meshes import buffer_places

    sizes = [(6, 6), (100, 8), (4, 100), (2, 2)]  # vertex 6 -> 8 bytes once aligned to 4
    assert buffer_places(sizes, 108, list("abcd")) == [(0, 0, 0), (0, 8, 8), (1, 0, 0), (1, 4, 100)]
    assert buffer_places(sizes, 10**6, list("abcd")) == [(0, 0, 0), (0, 8, 8), (0, 108, 16), (0, 112, 116)]
    with pytest.raises(UserError) as err:
        buffer_places(sizes, 99, list("abcd"))
    assert "\n" not in str(err.value) and "mesh b" in str(err.value) and "100-byte" in str(err.value)


def _largest_buffer(ctx, path, name) -> int:
    """The larger of the plane's interleaved vertex bytes (for the attributes its variant reads: the shader
    interface's interleave, not the packing under test) and its index bytes."""
    from wgpurender.core.models.mesh import load_mesh
    from wgpurender.wgpu_path.scene import load_renderer
    from wgpurender.wgpu_path.scene.shader_interface import interleave

    plan = load_renderer(path, ctx).plan
    draw = next(d for d in plan.scene_pass.draws if d.model_path.name == name)
    mesh = load_mesh(draw.model_path)
    return max(interleave(mesh, plan.variant(draw.variant_key).vertex_attributes).nbytes, len(mesh.index_bytes()))


def test_meshes_past_the_devices_max_buffer_size_go_into_more_pairs(ctx, tmp_path, monkeypatch):
    """The device's max-buffer-size lowered to the plane's larger buffer (lavapipe's is 2 GiB: no scene here
    reaches it): the triangle, the plane and the cube each need a pair of their own, and draw as before."""
    from wgpurender.wgpu_path.device.context import GPUContext
    from wgpurender.wgpu_path.scene import load_renderer

    path = _scene(tmp_path)
    limit = _largest_buffer(ctx, path, "plane.obj")
    real = GPUContext.limit
    monkeypatch.setattr(GPUContext, "limit", lambda self, key: limit if key == "max-buffer-size" else real(self, key))
    renderer = load_renderer(path, ctx)
    buffers = list(renderer.resources._buffers.values())
    assert len({id(b.vertex) for b in buffers}) == 3 and len({id(b.index) for b in buffers}) == 3
    assert all(b.vertex.size <= limit and b.index.size <= limit for b in buffers)
    _assert_each_colour_where_its_model_projects(ctx, renderer, path)


def test_one_mesh_past_the_devices_max_buffer_size_is_one_line(ctx, tmp_path, monkeypatch):
    from wgpurender.wgpu_path.device.context import GPUContext
    from wgpurender.wgpu_path.scene import load_renderer

    path = _scene(tmp_path)
    limit = _largest_buffer(ctx, path, "plane.obj") - 4
    real = GPUContext.limit
    monkeypatch.setattr(GPUContext, "limit", lambda self, key: limit if key == "max-buffer-size" else real(self, key))
    with pytest.raises(UserError) as err:
        load_renderer(path, ctx)
    assert "\n" not in str(err.value) and "plane.obj" in str(err.value) and f"({limit} bytes)" in str(err.value)
