"""Issue 31.3's load, per array instead of per model: a scene's model paths checked in one pass
(Checker.files_ahead, read_jail.inside_all), the draws' world matrices stacked per run (batches.stacked_worlds),
a draw's first instance set without copy.copy (batches._starting_at). Each gives what the per-model way gave,
and an error is the same one line about the same model. API-free."""

from __future__ import annotations

import dataclasses
import os
from types import SimpleNamespace

import numpy as np
import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail
from wgpurender.core.models import procedural
from wgpurender.core.plan import batches
from wgpurender.core.scene.checker import Checker
from wgpurender.core.scene.load import load_scene

SCENE = ("[camera]\neye = [0.0, 0.0, 5.0]\ntarget = [0.0, 0.0, 0.0]\n\n"
         "[materials.red]\nalbedo_color = [1.0, 0.0, 0.0]\n\n")


def _scene(folder, models: list[str], extra: dict[int, str] | None = None):
    extra = extra or {}
    text = SCENE + "".join(f'[[models]]\npath = "{m}"\n{extra.get(k, "")}\n' for k, m in enumerate(models))
    path = folder / "s.toml"
    path.write_text(text)
    return path


def _cubes(folder, names):
    for name in names:
        procedural.write_obj(folder / name, procedural.box(1.0))


def test_plain_files_are_found_ahead_as_file_finds_them(tmp_path, monkeypatch):
    monkeypatch.setattr(read_jail, "_CHECKED", set())
    _cubes(tmp_path, ["a.obj", "b.obj"])
    (tmp_path / "sub").mkdir()
    _cubes(tmp_path / "sub", ["c.obj"])
    ahead = Checker(tmp_path / "s.toml", "").files_ahead(["a.obj", "sub/c.obj", "b.obj"])
    assert ahead == [(tmp_path / n).resolve() for n in ("a.obj", "sub/c.obj", "b.obj")]
    assert read_jail._CHECKED == {os.fspath(p) for p in ahead}  # vouched: open_checked verifies what it opens
    for p in ahead:
        with read_jail.open_checked(p) as f:
            assert f.read() == p.read_bytes()


def test_anything_but_a_plain_file_inside_is_left_to_file(tmp_path, monkeypatch):
    monkeypatch.setattr(read_jail, "_CHECKED", set())
    project, away = tmp_path / "project", tmp_path / "away"
    project.mkdir()
    away.mkdir()
    _cubes(project, ["ok.obj"])
    _cubes(away, ["far.obj"])
    (project / "link.obj").symlink_to(project / "ok.obj")
    (project / "dir.obj").mkdir()
    values = ["ok.obj", "link.obj", "missing.obj", "dir.obj", "../away/far.obj", "o\nk.obj", 7, None]
    ahead = Checker(project / "s.toml", "").files_ahead(values)
    ok = (project / "ok.obj").resolve()
    assert ahead == [ok, ok] + [None] * 6  # a link inside is its target, as file() and pathlib resolve it
    assert read_jail._CHECKED == {os.fspath((project / "ok.obj").resolve())}  # nothing refused was vouched


def test_a_sibling_folder_with_the_same_prefix_is_outside():
    folders = [read_jail.Path("/x/proj")]
    got = read_jail.inside_all([read_jail.Path("/x/proj2/m.obj"), read_jail.Path("/x/proj/m.obj"),
                                read_jail.Path("/x/proj")], folders)
    assert got == [False, True, True]
    assert read_jail.inside_all([read_jail.Path("/a/b.obj")], [read_jail.Path("/")]) == [True]


def test_a_bundled_scene_lets_all_through_and_non_posix_is_left_to_outside(monkeypatch):
    assert read_jail.inside_all([read_jail.Path("/a"), read_jail.Path("/b")], None) == [True, True]
    monkeypatch.setattr(read_jail, "os", SimpleNamespace(name="nt", fspath=os.fspath))  # the rule's module only
    assert read_jail.inside_all([read_jail.Path("/a")], [read_jail.Path("/a")]) is None


def test_the_scene_loads_the_paths_found_ahead(tmp_path):
    names = [f"m{k}.obj" for k in range(6)]
    _cubes(tmp_path, names)
    (tmp_path / "l.obj").symlink_to(tmp_path / "m0.obj")  # left to file(): resolved to its target
    scene = load_scene(_scene(tmp_path, [*names, "l.obj"]))
    assert [m.path for m in scene.models] == [(tmp_path / n).resolve() for n in [*names, "m0.obj"]]


@pytest.mark.parametrize(("models", "extra", "where", "says"), [
    (["m0.obj", "gone.obj"], {0: 'material = "blue"'}, "models[0].material", "no material 'blue'"),
    (["gone.obj", "m0.obj"], {1: 'material = "blue"'}, "models[0].path", "'gone.obj' not found"),
    (["m0.obj", "m0.fbx2"], {}, "models[1].path", "unknown model format"),
    (["m0.obj", "m1.blend"], {}, "models[1].path", "Blender"),
])
def test_an_error_is_about_the_first_bad_model_in_order(tmp_path, models, extra, where, says):
    _cubes(tmp_path, ["m0.obj", "m0.fbx2", "m1.blend"])  # files that exist: the format check still refuses them
    with pytest.raises(UserError) as err:
        load_scene(_scene(tmp_path, models, extra))
    line = str(err.value)
    assert "\n" not in line and where in line and says in line


def test_a_path_outside_the_project_is_refused_by_the_rule(tmp_path):
    project, away = tmp_path / "project", tmp_path / "away"
    project.mkdir()
    away.mkdir()
    _cubes(project, ["m0.obj"])
    _cubes(away, ["far.obj"])
    with pytest.raises(UserError, match=r"models\[1\]\.path: .*outside the folders a scene may read"):
        load_scene(_scene(project, ["m0.obj", "../away/far.obj"]))


def _matrix(k: float) -> tuple:
    return tuple(tuple(float(k * 16 + 4 * r + c) for c in range(4)) for r in range(4))


def test_worlds_are_stacked_in_draw_order_across_runs():
    single = [SimpleNamespace(worlds=None, transform=_matrix(k)) for k in range(5)]
    copies = np.arange(3 * 16, dtype=np.float64).reshape(3, 4, 4) + 1000.0
    # an instanced draw keeps a transform too (its first copy's, batches.instanced): its worlds decide
    many = SimpleNamespace(worlds=object(), transform=_matrix(9), world_matrices=lambda: copies)
    draws = [single[0], single[1], many, single[2], many, single[3], single[4]]
    expected = [np.array(_matrix(0)), np.array(_matrix(1)), *copies, np.array(_matrix(2)), *copies,
                np.array(_matrix(3)), np.array(_matrix(4))]
    got = batches.stacked_worlds(draws)
    assert got.dtype == np.float64 and got.shape == (11, 4, 4)
    np.testing.assert_array_equal(got, np.array(expected))
    np.testing.assert_array_equal(batches.stacked_worlds([many]), copies)
    assert batches.stacked_worlds([]).shape == (0, 4, 4)


@dataclasses.dataclass(frozen=True)
class _Fields:
    a: int
    b: tuple
    first_instance: int = 0


def test_a_draw_moved_to_its_first_instance_keeps_every_other_field():
    draw = _Fields(3, (1, 2))
    moved = batches._starting_at(draw, 7)
    assert type(moved) is _Fields and moved == _Fields(3, (1, 2), 7) and moved.b is draw.b
    assert draw.first_instance == 0  # the plan's draw is not changed
    assert batches._starting_at(draw, 0) is draw
    with pytest.raises(dataclasses.FrozenInstanceError):
        moved.a = 1


def test_distinct_models_start_one_instance_apart(tmp_path):
    from wgpurender.core.plan import Knobs, resolve_knobs

    names = [f"m{k}.obj" for k in range(4)]
    _cubes(tmp_path, names)
    scene = load_scene(_scene(tmp_path, names, {k: f"transform = {{ translate = [{k}.0, 0.0, 0.0] }}"
                                                for k in range(4)}))
    plan = resolve_knobs(scene, Knobs())
    draws = plan.scene_pass.draws
    assert [d.first_instance for d in draws] == [0, 1, 2, 3]
    blocks = batches.instance_blocks(draws)
    assert [float(blocks[k, 12]) for k in range(4)] == [0.0, 1.0, 2.0, 3.0]  # column-major: x translation at 12


def _greedy_places(sizes, limit, strides):
    """The rule buffer_places' docstring states, step by step: each mesh at the end of the one before, rounded up
    to a whole vertex of its stride, both sizes rounded up to 4 bytes; a new pair where the limit would be passed."""
    places, pair, vertex_end, index_end = [], 0, 0, 0
    for (vertex, index), step in zip(sizes, strides, strict=True):
        vertex, index = -(-vertex // 4) * 4, -(-index // 4) * 4
        start = -(-vertex_end // step) * step
        if start + vertex > limit or index_end + index > limit:
            pair, start, index_end = pair + 1, 0, 0
        places.append((pair, start, index_end))
        vertex_end, index_end = start + vertex, index_end + index
    return places


@pytest.mark.parametrize("seed", range(6))
def test_places_in_one_pair_are_the_running_sums_of_the_rule(seed):
    from wgpurender.core.plan.meshes import _places_in_one_pair, buffer_places

    rng = np.random.default_rng(seed)
    stride = int(rng.choice([12, 32, 48]))
    n = int(rng.integers(1, 400))
    sizes = [(int(v) * stride, int(i) * 2) for v, i in zip(rng.integers(1, 50, n), rng.integers(1, 90, n), strict=True)]
    total = max(sum(v for v, _ in sizes), sum(-(-i // 4) * 4 for _, i in sizes))
    names = [f"m{k}" for k in range(n)]
    got = _places_in_one_pair(sizes, total, [stride] * n)
    assert got == _greedy_places(sizes, total, [stride] * n) == buffer_places(sizes, total, names, [stride] * n)
    assert all(p == 0 for p, _, _ in got)
    assert got[-1][1] == sum(v for v, _ in sizes[:-1]) and got[-1][2] == sum(-(-i // 4) * 4 for _, i in sizes[:-1])
    # a byte less than the total: no longer one pair, the loop decides (and still follows the rule)
    assert _places_in_one_pair(sizes, total - 1, [stride] * n) is None
    if n > 1:
        assert buffer_places(sizes, total - 1, names, [stride] * n) == _greedy_places(sizes, total - 1, [stride] * n)


def test_places_not_plain_are_left_to_the_loop():
    from wgpurender.core.plan.meshes import _places_in_one_pair, buffer_places

    sizes = [(48, 72), (96, 36), (48, 72)]
    assert _places_in_one_pair(sizes, 10**6, [48, 32, 48]) is None  # two strides
    assert buffer_places(sizes, 10**6, list("abc"), [48, 32, 48]) == _greedy_places(sizes, 10**6, [48, 32, 48])
    assert _places_in_one_pair([(40, 8), (48, 8)], 10**6, [48, 48]) is None  # 40 bytes: not a whole vertex
    assert buffer_places([(40, 8), (48, 8)], 10**6, list("ab"), [48, 48]) == [(0, 0, 0), (0, 48, 8)]
    assert _places_in_one_pair([], 10**6, []) is None
    assert _places_in_one_pair([(10, 6), (8, 2)], 10**6, None) == [(0, 0, 0), (0, 12, 8)]  # rounded up to 4
    assert _places_in_one_pair([(10, 6)], 10**6, [4, 4]) is None  # strides not one per mesh


def test_names_in_a_folder_resolve_as_one_by_one(tmp_path):
    from wgpurender.core.files.input_files import FolderResolver

    real = tmp_path / "real"
    real.mkdir()
    (tmp_path / "via").symlink_to(real)  # the folder itself through a link: resolved once
    _cubes(real, ["a.obj", "b.obj"])
    (real / "l.obj").symlink_to(real / "b.obj")
    (real / "d.obj").mkdir()
    values = ["a.obj", "l.obj", "d.obj", "gone.obj", "sub/a.obj", ".", "..", "", "x\ty.obj", 3]
    batch, single = FolderResolver(), FolderResolver()
    got = batch.names_in(os.fspath(tmp_path / "via"), values)
    plain = values[:4]
    assert got[:4] == [single(os.path.join(tmp_path / "via", v)) for v in plain]
    assert got[:4] == [real / "a.obj", real / "b.obj", real / "d.obj", real / "gone.obj"]
    assert got[4:] == [None] * 6  # left to the caller
    # only a name whose own lstat found a regular file (a link's target is checked again by input_file)
    assert [batch.regular(p) for p in got[:4]] == [single.regular(p) for p in got[:4]] == [True, False, False, False]
    assert batch(os.path.join(tmp_path / "via", "a.obj")) is got[0]  # one cache: asked again, the same result
    assert all(a is b for a, b in zip(batch.names_in(os.fspath(tmp_path / "via"), plain), got[:4], strict=True))
    assert batch(got[0]) is got[0]


def test_plain_model_paths_skip_the_per_file_check(tmp_path, monkeypatch):
    names = [f"m{k}.obj" for k in range(5)]
    _cubes(tmp_path, names)
    (tmp_path / "sub").mkdir()
    _cubes(tmp_path / "sub", ["s.obj"])
    asked = []
    real = Checker.file
    monkeypatch.setattr(Checker, "file", lambda self, value, *rest: asked.append(value) or real(self, value, *rest))
    scene = load_scene(_scene(tmp_path, [*names, "sub/s.obj"]))
    assert len(scene.models) == 6
    assert [v for v in asked if v.endswith(".obj")] == []  # the one pass found all six


def test_without_posix_paths_every_file_is_checked_one_by_one(tmp_path, monkeypatch):
    _cubes(tmp_path, ["a.obj"])
    monkeypatch.setattr(read_jail, "os", SimpleNamespace(name="nt", fspath=os.fspath, environ=os.environ,
                                                         pathsep=os.pathsep, path=os.path))
    assert Checker(tmp_path / "s.toml", "").files_ahead(["a.obj", "b.obj"]) == [None, None]


def test_the_rule_is_asked_once_when_each_file_is_checked_alone(tmp_path, monkeypatch):
    targets = [f"t{k}.obj" for k in range(4)]
    _cubes(tmp_path, targets)
    for k, name in enumerate(targets):
        (tmp_path / f"l{k}.obj").symlink_to(tmp_path / name)  # links: left to the per-model check, one by one
    asked = []
    real = read_jail.scene_folders
    monkeypatch.setattr(read_jail, "scene_folders", lambda scene: asked.append(scene) or real(scene))
    scene = load_scene(_scene(tmp_path, [f"l{k}.obj" for k in range(4)]))
    assert [m.path for m in scene.models] == [(tmp_path / n).resolve() for n in targets]
    assert len(asked) == 1
