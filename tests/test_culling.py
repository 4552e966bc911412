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


def write_scene(folder: Path, copies: int = COPIES) -> Path:
    procedural.write_obj(folder / "cube.obj", procedural.box(1.0))
    text = f"""
[camera]
eye = [0, 0, 12]
target = [0, 0, 0]
fov_y = 40
[[models]]
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
