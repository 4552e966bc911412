"""GPU frustum culling (issue 31.2), by pixels and by the count the GPU wrote.

A row of unlit white cubes runs far past both sides of the view. Culled, the image must equal the unculled
render (exactly: same run, same machine) and the raw path's (which draws every instance); the instance count
the culling pass wrote into the indirect draw must equal the number of bounding spheres that meet the frustum,
computed here from the camera's matrix with the plane test written out in numpy.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.models import procedural
from wgpurender.core.plan import Knobs as _Knobs
from wgpurender.core.plan import resolve_knobs
from wgpurender.core.plan.culling import GPU_CULL_MIN
from wgpurender.core.scene import parse_scene

SIZE = (96, 48)
COPIES = 15
SPACING = 3.0


def _resolved(scene, knobs=None, **overrides):
    """The plan through resolve_plan (core/plan/resolve.py), the knobs as one Knobs."""
    return resolve_knobs(scene, knobs or _Knobs(), **overrides)


CAMERA = "[camera]\neye = [0, 0, 12]\ntarget = [0, 0, 0]\nfov_y = 40\n"  # both scenes' view, down -z


def write_scene(folder: Path, copies: int = COPIES) -> Path:
    procedural.write_obj(folder / "cube.obj", procedural.box(1.0))
    text = CAMERA + f"""[[models]]
path = "cube.obj"
material = {{ albedo_color = [1, 1, 1], unlit = true }}
instances = {{ grid = [{copies}, 1, 1], spacing = [{SPACING}, 1, 1] }}
[render]
size = [{SIZE[0]}, {SIZE[1]}]
msaa = 1
"""
    (folder / "row.toml").write_text(text)
    return folder / "row.toml"


def spheres_in_view(path: Path) -> int:
    """How many unit cubes' bounding spheres (radius sqrt(3)/2) meet the frustum: the plane test from the clip
    matrix's rows, x and y within +-w and 0 <= z <= w."""
    scene = parse_scene(path.read_text(), path)
    m = scene.camera.projection(SIZE[0] / SIZE[1]) @ scene.camera.view()
    planes = [m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[2], m[3] - m[2]]
    radius = np.sqrt(3) / 2
    count = 0
    for k in range(COPIES):
        centre = np.array([(k - (COPIES - 1) / 2) * SPACING, 0.0, 0.0, 1.0])
        count += all(p @ centre >= -radius * np.linalg.norm(p[:3]) for p in planes)
    return count


def test_culled_image_equals_the_unculled_and_raw_and_counts_what_is_in_view(ctx, tmp_path):
    from wgpurender.raw_path.render import render_reference
    from wgpurender.wgpu_path.scene import load_renderer, render_frame

    path = write_scene(tmp_path)
    culled = load_renderer(path, ctx, knobs={"culling": "gpu"})
    plain = load_renderer(path, ctx, knobs={"culling": "off"})
    assert culled.plan.setting("culling") == "gpu" and plain.plan.setting("culling") == "off"
    a, _ = render_frame(ctx, culled, culled.create_output())
    b, _ = render_frame(ctx, plain, plain.create_output())
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(a, render_reference(str(path), size=None))
    args = np.frombuffer(ctx.read_buffer(culled.scene_pass.culler.indirect), np.uint32)
    want = spheres_in_view(path)
    assert 0 < want < COPIES  # the scene has copies on both sides of the view and in it
    assert args[1] == want  # instance_count, as the culling pass counted it
    assert args[0] == 36 and args[4] == 0  # the cube's 36 indices; its instances start at 0
    lit = a[..., :3].max(axis=2) > 200
    scene = parse_scene(path.read_text(), path)
    m = scene.camera.projection(SIZE[0] / SIZE[1]) @ scene.camera.view()
    seen = 0
    for k in range(COPIES):  # every copy whose centre is in the image is drawn there
        c = m @ np.array([(k - (COPIES - 1) / 2) * SPACING, 0.0, 0.0, 1.0])
        x, y = (c[0] / c[3] + 1) / 2 * SIZE[0], (1 - c[1] / c[3]) / 2 * SIZE[1]
        if 0 <= x < SIZE[0]:
            assert lit[int(y), int(x)], k
            seen += 1
    assert 0 < seen <= want


def test_plan_culls_large_draws_only(tmp_path):
    from wgpurender.core.plan.model import AdapterFacts, Knobs

    facts = AdapterFacts("DiscreteGPU", frozenset({"indirect-first-instance"}))
    small = _resolved(parse_scene(write_scene(tmp_path).read_text(), tmp_path / "row.toml"),
                       knobs=Knobs(adapter=facts))
    assert small.setting("culling") == "off" and not small.culled_draws
    assert "no draw qualifies" in small.explain()
    big_path = write_scene(tmp_path, GPU_CULL_MIN)
    big = _resolved(parse_scene(big_path.read_text(), big_path), knobs=Knobs(adapter=facts))
    assert big.setting("culling") == "gpu" and len(big.culled_draws) == 1
    assert [p.culled for p in big.pipelines] == [True]  # the unculled pipeline is no longer listed
    text = big.explain()
    assert f"({GPU_CULL_MIN} instances)" in text and "GPU frustum culling" in text
    assert "scene-visible" in text and "scene-indirect" in text
    bare = _resolved(parse_scene(big_path.read_text(), big_path), knobs=Knobs(adapter=AdapterFacts("DiscreteGPU")))
    assert bare.setting("culling") == "off" and "lacks 'indirect-first-instance'" in bare.explain()
    off = _resolved(parse_scene(big_path.read_text(), big_path), knobs=Knobs(adapter=facts, culling="off"))
    assert off.setting("culling") == "off" and not off.culled_draws


def test_bad_culling_knob_is_refused(tmp_path):
    from wgpurender.core.errors import UserError
    from wgpurender.core.plan.model import Knobs

    path = write_scene(tmp_path)
    with pytest.raises(UserError, match="culling"):
        _resolved(parse_scene(path.read_text(), path), knobs=Knobs(culling="sometimes"))


def test_bounding_sphere_holds_every_vertex():
    from wgpurender.wgpu_path.scene.culling import bounding_sphere

    points = np.array([(0.0, 0.0, 0.0), (4.0, 0.0, 0.0), (2.0, 0.1, 0.0), (0.0, 2.0, 0.0)])
    centre, radius = bounding_sphere(points)
    np.testing.assert_array_equal(centre, (2.0, 1.0, 0.0))  # the bounding box's centre
    assert radius == pytest.approx(np.sqrt(5.0))  # the farthest vertex (0.9 is the nearest)


# A triangle, then a 3x2 grid of cubes: the grid's mesh lies after the triangle's in the shared vertex and index
# buffers. Its GPU-culled draw once bound its indices at their byte offset there with first index 0 in the
# indirect block, and lavapipe's indirect draws ignore that offset (benchmarks/indirect_index_offset_probe.py):
# every cube lost triangles (48 of 72 pixels), the image silently wrong.
GRID, GRID_SPACING, CUBE, GRID_SIZE = (3, 2), 1.5, 1.0, (128, 64)
TRIANGLE = "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0 0.5 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n"


def write_grid_after_triangle(folder: Path) -> Path:
    (folder / "tri.obj").write_text(TRIANGLE)
    procedural.write_obj(folder / "cube.obj", procedural.box(CUBE))
    text = CAMERA + f"""[[models]]
path = "tri.obj"
material = {{ albedo_color = [1, 0, 0], unlit = true }}
transform = {{ translate = [-4.5, 0, 0] }}
[[models]]
path = "cube.obj"
material = {{ albedo_color = [0, 0, 1], unlit = true }}
instances = {{ grid = [{GRID[0]}, {GRID[1]}, 1], spacing = [{GRID_SPACING}, {GRID_SPACING}, 1] }}
[render]
size = [{GRID_SIZE[0]}, {GRID_SIZE[1]}]
msaa = 1
"""
    (folder / "grid.toml").write_text(text)
    return folder / "grid.toml"


def assert_every_cube_whole(image: np.ndarray, path: Path) -> None:
    """Each cube's front face, projected from the scene's numbers (copy (i, j) at ((i, j) - (n - 1) / 2) *
    spacing, core/scene/instances.py), is blue at every pixel centre at least a pixel inside its edges, and its
    centre's pixel too."""
    scene = parse_scene(path.read_text(), path)
    m = scene.camera.projection(GRID_SIZE[0] / GRID_SIZE[1]) @ scene.camera.view()
    blue = (image[..., 2] > 200) & (image[..., 0] < 50)

    def pixel(p):
        c = m @ np.array([*p, 1.0])
        return (c[0] / c[3] + 1) / 2 * GRID_SIZE[0], (1 - c[1] / c[3]) / 2 * GRID_SIZE[1]

    for i in range(GRID[0]):
        for j in range(GRID[1]):
            x, y = (i - (GRID[0] - 1) / 2) * GRID_SPACING, (j - (GRID[1] - 1) / 2) * GRID_SPACING
            h = CUBE / 2
            (x0, y0), (x1, y1) = pixel((x - h, y + h, h)), pixel((x + h, y - h, h))
            cx, cy = pixel((x, y, 0.0))
            assert blue[int(cy), int(cx)], (i, j)
            xs = [c for c in range(GRID_SIZE[0]) if x0 + 1 <= c + 0.5 <= x1 - 1]
            ys = [r for r in range(GRID_SIZE[1]) if y0 + 1 <= r + 0.5 <= y1 - 1]
            assert len(xs) >= 3 and len(ys) >= 3  # the face is several pixels wide
            assert blue[np.ix_(ys, xs)].all(), (i, j, int(blue[np.ix_(ys, xs)].sum()), len(xs) * len(ys))


def test_culled_grid_after_another_draw_is_whole_on_both_paths(ctx, tmp_path):
    from wgpurender.core.plan import resolve_plan
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.scene.frame import render_scene_plan
    from wgpurender.wgpu_path.scene import load_renderer, render_frame

    path = write_grid_after_triangle(tmp_path)
    culled = load_renderer(path, ctx, knobs={"culling": "gpu"})
    plain = load_renderer(path, ctx, knobs={"culling": "off"})
    assert [d.instance_count for d in culled.plan.culled_draws] == [GRID[0] * GRID[1]]
    assert culled.plan.culled_draws[0].first_instance == 1  # after the triangle's one instance
    a, _ = render_frame(ctx, culled, culled.create_output())
    b, _ = render_frame(ctx, plain, plain.create_output())
    assert_every_cube_whole(a, path)
    assert_every_cube_whole(b, path)
    np.testing.assert_array_equal(a, b)
    facts = get_vulkan().adapter_facts()
    raw = {k: render_scene_plan(resolve_plan(path, facts, culling=k)) for k in ("gpu", "off")}
    np.testing.assert_array_equal(raw["gpu"], raw["off"])
    assert_every_cube_whole(raw["gpu"], path)
