"""Instancing and batching (issue 31.1): a model's ``instances`` block, the plan's batches, both paths' pixels.

Expectations come from the scene text (grid formula, counts) and from independent renders: the same copies
written as separate models of *different* mesh files (so nothing batches and each is its own draw), and the
raw Vulkan path; per-instance blocks against the raw path's hand packer (raw_path/device/uniforms.pack_object).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.models import procedural
from wgpurender.core.plan import Knobs as _Knobs
from wgpurender.core.plan import resolve_knobs
from wgpurender.core.plan.batches import instance_blocks
from wgpurender.core.scene import parse_scene
from wgpurender.core.view import transforms
from wgpurender.raw_path.device.uniforms import pack_object

SIZE = (96, 64)
HEAD = """
[camera]
eye = [0, 0, 9]
target = [0, 0, 0]
fov_y = 40
[materials.white]
albedo_color = [1, 1, 1]
unlit = true
"""
RENDER = f"\n[render]\nsize = [{SIZE[0]}, {SIZE[1]}]\nmsaa = 1\n"


def _resolved(scene, knobs=None, **overrides):
    """The plan through resolve_plan (core/plan/resolve.py), the knobs as one Knobs."""
    return resolve_knobs(scene, knobs or _Knobs(), **overrides)


@pytest.fixture(autouse=True)
def read_the_shared_cube(monkeypatch, tmp_path_factory):
    """The cube is written once for the module; scenes in other temporary folders may read it."""
    monkeypatch.setenv("WGPURENDER_ALLOW_PATHS", str(tmp_path_factory.getbasetemp()))


@pytest.fixture(scope="module")
def cube(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("inst")
    procedural.write_obj(folder / "cube.obj", procedural.box(1.0))
    return folder / "cube.obj"


def scene_file(folder: Path, body: str, lit: bool = False) -> Path:
    light = '\n[[lights]]\ntype = "directional"\ndirection = [-1, -1, -2]\n' if lit else ""
    path = folder / "scene.toml"
    path.write_text(HEAD + body + light + RENDER)
    return path


def model(path: Path, material: str = '"white"', extra: str = "") -> str:
    return f'\n[[models]]\npath = "{path.as_posix()}"\nmaterial = {material}\n{extra}\n'


# -- the scene file ------------------------------------------------------------------------------------------
def test_grid_places_copies_by_the_formula(cube):
    scene = parse_scene(HEAD + model(cube, extra="instances = { grid = [3, 2, 1], spacing = [2, 4, 1] }"),
                        cube.parent / "s.toml")
    m = scene.models[0]
    assert m.instance_count == 6
    offsets = m.worlds()[:, :3, 3]
    # copy (i, j) at ((i, j) - (n - 1) / 2) * spacing, i fastest
    want = [((i - 1) * 2.0, (j - 0.5) * 4.0, 0.0) for j in range(2) for i in range(3)]
    np.testing.assert_array_equal(offsets, want)


def test_model_transform_is_the_copies_parent(cube):
    text = model(cube, extra='transform = { translate = [10, 0, 0], scale = 2 }\n'
                              'instances = { translate = [[1, 0, 0], [0, 3, 0]] }')
    worlds = parse_scene(HEAD + text, cube.parent / "s.toml").models[0].worlds()
    # world = transform @ placement: the offsets are scaled by the parent, then moved by it
    np.testing.assert_array_equal(worlds[:, :3, 3], [(12, 0, 0), (10, 6, 0)])
    np.testing.assert_array_equal(worlds[:, 0, 0], [2, 2])


def test_npy_file_of_matrices_and_offsets(cube, tmp_path):
    mats = np.stack([transforms.translate((k, 0, 0)) @ transforms.scale((1, 1, 1 + k)) for k in range(3)])
    np.save(tmp_path / "m.npy", mats)
    np.save(tmp_path / "t.npy", np.array([[0, 1, 2], [3, 4, 5]], dtype=np.float32))
    s1 = parse_scene(HEAD + model(cube, extra='instances = { file = "m.npy" }'), tmp_path / "s.toml")
    s2 = parse_scene(HEAD + model(cube, extra='instances = { file = "t.npy" }'), tmp_path / "s.toml")
    np.testing.assert_allclose(s1.models[0].worlds(), mats)
    np.testing.assert_array_equal(s2.models[0].worlds()[:, :3, 3], [[0, 1, 2], [3, 4, 5]])


@pytest.mark.parametrize("block, words", [
    ("{ grid = [2, 2, 2], translate = [[0, 0, 0]] }", "exactly one of grid, translate or file"),
    ("{ }", "exactly one of grid, translate or file"),
    ("{ grid = [2, 2] }", "grid must be 3 counts"),
    ("{ grid = [2, 0, 1] }", "grid"),
    ("{ grid = [2000, 2000, 2] }", "more than the 4000000 allowed"),
    ("{ translate = [] }", "non-empty array"),
    ("{ translate = [[0, 0]] }", "array of 3 numbers"),
    ("{ translate = [[0, 0, 0]], spacing = [1, 1, 1] }", "spacing only applies to grid"),
    ("{ file = 'missing.npy' }", "missing.npy"),
    ("{ file = 'bad.txt' }", ".npy file"),
    ("{ file = 'nan.npy' }", "NaN"),
    ("{ file = 'shape.npy' }", "shape (2, 2)"),
    ("{ file = 'flat.npy' }", "singular"),
    ("{ file = 'junk.npy' }", "not a readable .npy"),
    ("{ grids = [1, 1, 1] }", "grids"),
])
def test_bad_instances_block_is_one_line(cube, tmp_path, block, words):
    (tmp_path / "bad.txt").write_text("x")
    np.save(tmp_path / "nan.npy", np.array([[np.nan, 0, 0]]))
    np.save(tmp_path / "shape.npy", np.zeros((2, 2)))
    np.save(tmp_path / "flat.npy", np.zeros((1, 4, 4)))
    (tmp_path / "junk.npy").write_bytes(b"\x93NUMPY garbage")
    with pytest.raises(UserError) as err:
        parse_scene(HEAD + model(cube, extra=f"instances = {block}"), tmp_path / "s.toml")
    text = str(err.value)
    assert words in text and "\n" not in text and "instances" in text


# -- the plan --------------------------------------------------------------------------------------------------
def test_ten_thousand_copies_are_one_draw(cube):
    scene = parse_scene(HEAD + model(cube, extra="instances = { grid = [100, 100, 1] }"), cube.parent / "s.toml")
    plan = _resolved(scene)
    assert len(plan.scene_pass.draws) == 1
    assert plan.scene_pass.draws[0].instance_count == 10_000
    small = _resolved(parse_scene(HEAD + model(cube, extra="instances = { grid = [2, 1, 1] }"),
                                   cube.parent / "s.toml"))
    assert plan.object_counts() == small.object_counts()  # O(1) in the count: every GPU object, by kind


def test_separate_models_of_one_mesh_and_material_batch(cube):
    body = "".join(model(cube, extra=f"transform = {{ translate = [{k}, 0, 0] }}") for k in range(5))
    body += model(cube, material='{ albedo_color = [1, 0, 0], unlit = true }')  # other values: its own draw
    plan = _resolved(parse_scene(HEAD + body, cube.parent / "s.toml"))
    draws = plan.scene_pass.draws
    assert [d.instance_count for d in draws] == [5, 1]
    assert [d.first_instance for d in draws] == [0, 5]
    text = plan.explain()
    assert "batch: instances 0..4 <- 5 draws (models[0], models[1], models[2] and 2 more) share mesh" in text
    assert "6 object(s) in 2 draw(s)" in text


def test_equal_materials_share_one_bind_group(cube, tmp_path):
    other = tmp_path / "other.obj"
    shutil.copy(cube, other)
    tex = tmp_path / "t.png"
    from wgpurender.core.files.imageio import save_png
    save_png(tex, np.full((4, 4, 4), 200, np.uint8))
    textured = f'{{ albedo_map = "{tex.as_posix()}", unlit = true }}'
    body = model(cube, material=textured) + model(other, material=textured)  # two meshes: two draws
    plan = _resolved(parse_scene(HEAD + body, tmp_path / "s.toml"))
    assert len(plan.scene_pass.draws) == 2
    groups = [o for o in plan.objects if o.kind == "bind_group" and o.name.startswith("material")]
    assert [g.count for g in groups] == [1]


def test_blended_draws_are_never_batched(cube):
    from dataclasses import replace

    from wgpurender.core.plan.batches import batch_draws

    plan = _resolved(parse_scene(HEAD + model(cube), cube.parent / "s.toml"))
    (draw,) = plan.scene_pass.draws
    twins = [replace(draw, label=f"twin {k}", transform=tuple(map(tuple, transforms.translate((k, 0, 0)))))
             for k in range(3)]
    assert [d.instance_count for d in batch_draws(twins, {draw.pipeline_key: False})] == [3]
    blended = batch_draws(twins, {draw.pipeline_key: True})  # glTF BLEND: scene order kept, one draw each
    assert [(d.label, d.instance_count, d.first_instance) for d in blended] == [
        ("twin 0", 1, 0), ("twin 1", 1, 1), ("twin 2", 1, 2)]


def test_mirrored_copies_get_their_own_draw(cube, tmp_path):
    np.save(tmp_path / "m.npy", np.stack([np.eye(4), np.diag([-1.0, 1, 1, 1]), transforms.translate((2, 0, 0))]))
    plan = _resolved(parse_scene(HEAD + model(cube, extra='instances = { file = "m.npy" }'), tmp_path / "s.toml"))
    draws = plan.scene_pass.draws
    assert [d.instance_count for d in draws] == [2, 1]
    assert [plan.pipeline(d.pipeline_key).front_face for d in draws] == ["ccw", "cw"]


def test_instance_blocks_match_the_hand_packer(cube, tmp_path):
    rng = np.random.default_rng(3)
    mats = np.stack([transforms.translate(rng.normal(size=3)) @ transforms.rotate(rng.normal(size=3), k)
                     @ transforms.scale(rng.uniform(0.2, 2, 3) * (-1 if k % 2 else 1)) for k in range(6)])
    np.save(tmp_path / "m.npy", mats)
    plan = _resolved(parse_scene(HEAD + model(cube, extra='instances = { file = "m.npy" }'), tmp_path / "s.toml"))
    blocks = instance_blocks(plan.scene_pass.draws)
    order = np.concatenate([d.world_matrices() for d in plan.scene_pass.draws])
    assert blocks.tobytes() == b"".join(pack_object(w) for w in order)
    assert sorted(map(tuple, order.reshape(6, -1))) == sorted(map(tuple, mats.astype(np.float32)
                                                                   .astype(np.float64).reshape(6, -1)))


# -- pixels, both paths ------------------------------------------------------------------------------------------
def render_both(path: Path, ctx):
    from wgpurender.raw_path.render import render_reference
    from wgpurender.wgpu_path.scene import render_scene_file

    return render_scene_file(path, ctx=ctx, frames=1).pixels, render_reference(str(path), size=None)


def separate_copies(folder: Path, cube: Path, worlds: np.ndarray) -> str:
    """Each copy as its own model of its own mesh file (so nothing batches), at its world matrix."""
    out = []
    for k, w in enumerate(worlds):
        own = folder / f"cube_{k}.obj"
        shutil.copy(cube, own)
        rows = ", ".join("[" + ", ".join(repr(float(v)) for v in r) + "]" for r in w)
        out.append(model(own, extra=f"transform = {{ matrix = [{rows}] }}"))
    return "".join(out)


@pytest.mark.parametrize("lit", [False, True])
def test_instanced_scene_equals_separate_models_on_both_paths(ctx, cube, tmp_path, lit):
    np.save(tmp_path / "m.npy", np.stack([transforms.translate((-2.2, 0.8, 0)) @ transforms.rotate((1, 1, 0), 0.5),
                                          transforms.translate((0, -0.9, 0)) @ np.diag([-0.8, 0.8, 0.8, 1]),
                                          transforms.translate((2.3, 0.5, -1)) @ transforms.rotate((0, 1, 0), 0.9)]))
    material = '{ albedo_color = [0.9, 0.6, 0.3] }' if lit else '"white"'
    inst = tmp_path / "a"
    inst.mkdir()
    shutil.copy(tmp_path / "m.npy", inst / "m.npy")
    a = scene_file(inst, model(cube, material, 'instances = { file = "m.npy" }'), lit)
    worlds = parse_scene(a.read_text(), a).models[0].worlds()
    sep = tmp_path / "b"
    sep.mkdir()
    b_text = separate_copies(sep, cube, worlds).replace('material = "white"', f"material = {material}")
    b = scene_file(sep, b_text, lit)
    assert len(_resolved(parse_scene(b.read_text(), b)).scene_pass.draws) == 3  # the reference is unbatched
    wgpu_a, raw_a = render_both(a, ctx)
    wgpu_b, raw_b = render_both(b, ctx)
    assert (wgpu_a.reshape(-1, 4)[:, :3] > 0).any(axis=1).mean() > 0.03  # the copies cover ~5% of it
    np.testing.assert_array_equal(wgpu_a, wgpu_b)
    np.testing.assert_array_equal(raw_a, raw_b)
    np.testing.assert_array_equal(wgpu_a, raw_a)


def test_grid_copies_are_where_the_camera_projects_them(ctx, cube, tmp_path):
    from wgpurender.wgpu_path.scene import render_scene_file

    path = scene_file(tmp_path, model(cube, extra="transform = { scale = 0.5 }\n"
                                                  "instances = { grid = [4, 3, 1], spacing = [2, 1.5, 1] }"))
    img = render_scene_file(path, ctx=ctx, frames=1).pixels
    scene = parse_scene(path.read_text(), path)
    clip_from_world = scene.camera.projection(SIZE[0] / SIZE[1]) @ scene.camera.view()
    lit = img[..., :3].max(axis=2) > 128
    for j in range(3):
        for i in range(4):
            centre = np.array([(i - 1.5) * 2 * 0.5, (j - 1) * 1.5 * 0.5, 0, 1])  # the parent's scale 0.5 too
            c = clip_from_world @ centre
            x = (c[0] / c[3] + 1) / 2 * SIZE[0]
            y = (1 - c[1] / c[3]) / 2 * SIZE[1]
            assert lit[int(y), int(x)], (i, j)
            gap = clip_from_world @ (centre + [0.5, 0, 0, 0])  # half-way to the next copy: background
            gx, gy = (gap[0] / gap[3] + 1) / 2 * SIZE[0], (1 - gap[1] / gap[3]) / 2 * SIZE[1]
            if 0 <= gx < SIZE[0]:
                assert not lit[int(gy), int(gx)], (i, j)
    assert lit.sum() < 0.5 * lit.size


def test_consecutive_draws_of_one_pipeline_bind_their_own_mesh_and_textures(ctx, cube, tmp_path):
    """Two draws in a row on one pipeline: a small box with a red texture on the left, a big box with a blue one
    on the right. The bundle skips state that did not change; what did change must be set again."""
    from wgpurender.core.files.imageio import save_png
    from wgpurender.wgpu_path.scene import render_scene_file

    big = tmp_path / "big.obj"
    procedural.write_obj(big, procedural.box(2.0))
    for name, rgb in (("red", (255, 0, 0)), ("blue", (0, 0, 255))):
        save_png(tmp_path / f"{name}.png", np.full((4, 4, 4), (*rgb, 255), np.uint8))
    body = (model(cube, f'{{ albedo_map = "{(tmp_path / "red.png").as_posix()}", unlit = true }}',
                  "transform = { translate = [-2, 0, 0] }")
            + model(big, f'{{ albedo_map = "{(tmp_path / "blue.png").as_posix()}", unlit = true }}',
                    "transform = { translate = [2, 0, 0] }"))
    path = scene_file(tmp_path, body)
    plan = _resolved(parse_scene(path.read_text(), path))
    assert len(plan.pipelines) == 1 and len(plan.scene_pass.draws) == 2
    img = render_scene_file(path, ctx=ctx, frames=1).pixels
    scene = parse_scene(path.read_text(), path)
    clip_from_world = scene.camera.projection(SIZE[0] / SIZE[1]) @ scene.camera.view()

    def pixel(p):
        c = clip_from_world @ np.array([*p, 1.0])
        return img[int((1 - c[1] / c[3]) / 2 * SIZE[1]), int((c[0] / c[3] + 1) / 2 * SIZE[0]), :3].tolist()

    assert pixel((-2, 0, 0)) == [255, 0, 0]
    assert pixel((2, 0, 0)) == [0, 0, 255]
    assert pixel((2.8, 0.8, 1.0)) == [0, 0, 255]  # inside the big box's front face only (the small one ends at 0.5)
