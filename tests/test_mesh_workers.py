"""A scene's OBJ files read by worker processes (core/models/mesh_workers.py) when the plan says so
(core/plan/mesh_loading.py, knob mesh_workers): the same meshes as this process reads, the same one-line
refusal (the first refused file in draw order), the read rule still applied by the parent, a dead worker
answered by a serial read, and the decision shown by --explain."""

from __future__ import annotations

import os

import numpy as np
import pytest
from helpers import same_mesh as _same

from wgpurender.core.errors import UserError
from wgpurender.core.models import obj_cached, obj_cached_chunks, procedural
from wgpurender.core.models.mesh import load_mesh
from wgpurender.core.plan import mesh_loading, resolve_plan
from wgpurender.core.plan import meshes as plan_meshes
from wgpurender.core.plan.meshes import PlanMeshes

pytestmark = pytest.mark.skipif(not mesh_loading.can_fork(), reason="worker processes need fork (Linux)")

CAMERA = "[camera]\neye = [0.0, 0.0, 30.0]\ntarget = [0.0, 0.0, 0.0]\n\n"
NAN_CUBE = "v nan 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n"


@pytest.fixture(autouse=True)
def own_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))


def _scene(folder, names, extra: str = ""):
    text = CAMERA + "".join(f'[[models]]\npath = "{n}"\ntransform = {{ translate = [{k % 7}, {k // 7}, 0] }}\n\n'
                            for k, n in enumerate(names)) + extra
    path = folder / "s.toml"
    path.write_text(text)
    return path


def _cubes(folder, n):
    names = []
    for k in range(n):
        mesh = procedural.box(0.5 + 0.01 * k)  # distinct files
        procedural.write_obj(folder / f"c{k}.obj", mesh)
        names.append(f"c{k}.obj")
    return names


def _meshes(plan):
    meshes = PlanMeshes(plan)
    return [meshes.mesh(d.mesh_key) for d in plan.scene_pass.draws]


def test_workers_read_the_meshes_this_process_reads(tmp_path):
    names = _cubes(tmp_path, 12)
    (tmp_path / "bare.obj").write_text(  # not simple (a group record): the parent's general loader reads it
        "o thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    scene = _scene(tmp_path, [*names, "bare.obj"])
    on = resolve_plan(scene, None, mesh_workers="on")
    off = resolve_plan(scene, None, mesh_workers="off")
    assert on.mesh_workers == 1 and off.mesh_workers == 0  # 13 files: one worker per 64
    here = []  # what this process loads itself: only the file that is not a simple OBJ
    real = plan_meshes.load_mesh
    with pytest.MonkeyPatch.context() as m:
        m.setattr(plan_meshes, "load_mesh", lambda path, **kw: here.append(path.name) or real(path, **kw))
        served = _meshes(on)
    assert here == ["bare.obj"]
    # what the worker parsed, it stored as one entry for its one chunk (no entry per file)
    assert len(list(obj_cached.folder().glob("*.meshes"))) == 1
    assert list(obj_cached.folder().glob("*.mesh")) == []
    assert len(served) == 13
    for got, want, draw in zip(served, _meshes(off), on.scene_pass.draws, strict=True):
        _same(got, want)
        _same(got, load_mesh(draw.model_path, generate_tangents=False))
    for k, got in enumerate(served[:12]):  # each cube is the size its file says
        assert np.allclose(np.ptp(got.positions, axis=0), 0.5 + 0.01 * k, atol=1e-6)


def test_a_refusal_in_a_worker_is_the_same_one_line_for_the_first_bad_file(tmp_path):
    names = _cubes(tmp_path, 5)
    (tmp_path / "bad1.obj").write_text(NAN_CUBE)
    (tmp_path / "bad2.obj").write_text(NAN_CUBE)
    scene = _scene(tmp_path, [*names[:2], "bad1.obj", names[2], "bad2.obj"])
    messages = []
    for knob in ("on", "off"):
        with pytest.raises(UserError) as err:
            _meshes(resolve_plan(scene, None, mesh_workers=knob))
        messages.append(str(err.value))
    assert messages[0] == messages[1]
    assert "bad1.obj" in messages[0] and "NaN" in messages[0] and "\n" not in messages[0]


def test_the_size_limit_holds_in_a_worker(tmp_path, monkeypatch):
    names = _cubes(tmp_path, 3)
    scene = _scene(tmp_path, names)
    limit = min((tmp_path / n).stat().st_size for n in names) - 1
    monkeypatch.setenv("WGPURENDER_MAX_MODEL_BYTES", str(limit))
    messages = []
    for knob in ("on", "off"):
        with pytest.raises(UserError) as err:
            _meshes(resolve_plan(scene, None, mesh_workers=knob))
        messages.append(str(err.value))
    assert messages[0] == messages[1] and "c0.obj" in messages[0] and "over the limit" in messages[0]


def test_a_normal_mapped_model_gets_its_tangents_from_a_worker(tmp_path):
    from wgpurender.core.files.imageio import save_png

    save_png(tmp_path / "n.png", np.full((4, 4, 4), (128, 128, 255, 255), np.uint8))
    names = _cubes(tmp_path, 2)
    scene = _scene(tmp_path, names, '[[lights]]\ntype = "directional"\ndirection = [0, 0, -1]\n')
    text = scene.read_text().replace('path = "c1.obj"\n', 'path = "c1.obj"\nmaterial = { normal_map = "n.png" }\n')
    scene.write_text(text)
    served = _meshes(resolve_plan(scene, None, mesh_workers="on"))
    assert served[0].tangents is None and served[1].tangents is not None
    _same(served[1], load_mesh(tmp_path / "c1.obj", generate_tangents=True))


def test_the_read_rule_is_the_parents_before_any_worker(tmp_path):
    outside = tmp_path / "outside"
    outside.mkdir()
    procedural.write_obj(outside / "m.obj", procedural.box(1.0))
    mine = tmp_path / "project" / "deep"
    mine.mkdir(parents=True)
    (mine / "link.obj").symlink_to(outside / "m.obj")  # a link in the scene's folder to a file outside it
    for name in ("../../outside/m.obj", "link.obj"):
        with pytest.raises(UserError, match="outside the folders a scene may read"):
            resolve_plan(_scene(mine, [name]), None, mesh_workers="on")


def test_a_dead_worker_leaves_the_rest_to_this_process(tmp_path, monkeypatch):
    names = _cubes(tmp_path, 3)
    scene = _scene(tmp_path, names)
    parent = os.getpid()
    real = obj_cached_chunks.meshes

    def dies_in_a_worker(*args):
        if os.getpid() != parent:  # the forked worker has this module as patched here
            os._exit(3)
        return real(*args)

    monkeypatch.setattr(obj_cached_chunks, "meshes", dies_in_a_worker)
    general = []  # the chunks a dead worker left are read here the same way, not by the general loader
    real_general = plan_meshes.load_mesh
    monkeypatch.setattr(plan_meshes, "load_mesh", lambda path, **kw: general.append(path) or real_general(path, **kw))
    served = _meshes(resolve_plan(scene, None, mesh_workers="on"))
    assert general == []
    for got, name in zip(served, names, strict=True):
        _same(got, load_mesh(tmp_path / name, generate_tangents=False))


@pytest.mark.parametrize("knob, files, cores, fork, workers", [
    ("auto", mesh_loading.MIN_FILES - 1, 16, True, 0),  # too few files to pay for a pool
    ("auto", mesh_loading.MIN_FILES, 16, True, 4),  # one worker per 64 files
    ("auto", 10_000, 16, True, 16),  # one per core
    ("auto", 10_000, 64, True, mesh_loading.MAX_WORKERS),
    ("auto", 10_000, 1, True, 0),
    ("auto", 10_000, 16, False, 0),  # no fork: no pool
    ("off", 10_000, 16, True, 0),
    ("on", 3, 16, True, 1),
    ("on", 65, 16, True, 2),  # 65 files: two workers (one per 64, rounded up)
    ("on", 0, 16, True, 0),
])
def test_the_rule(knob, files, cores, fork, workers):
    got, why = mesh_loading.resolve_mesh_workers(knob, files, cores=cores, fork=fork)
    assert got == workers and why and "\n" not in why
    if workers:
        assert str(workers) in why


def test_on_where_no_worker_can_start_is_refused_not_dropped():
    """mesh_workers = on without the fork start method read in this process and said so only in --explain: a
    knob asked for by name that cannot apply is refused in one line (auto falls back, as its rule says)."""
    with pytest.raises(UserError, match=r"mesh_workers = on: worker processes need the fork start method"):
        mesh_loading.resolve_mesh_workers("on", 300, cores=16, fork=False)
    assert mesh_loading.resolve_mesh_workers("auto", 300, cores=16, fork=False)[0] == 0


def test_an_unknown_knob_is_one_line():
    with pytest.raises(UserError, match=r"mesh_workers = 'many': choose one of auto, off, on"):
        mesh_loading.resolve_mesh_workers("many", 10)


def test_explain_says_how_the_files_are_read(tmp_path):
    scene = _scene(tmp_path, _cubes(tmp_path, 3))
    text = resolve_plan(scene, None).explain()
    assert f"mesh_workers: 0 <- 3 OBJ file(s), fewer than {mesh_loading.MIN_FILES}" in text
    text = resolve_plan(scene, None, mesh_workers="on").explain()
    assert "mesh_workers: 1 <- knob mesh_workers = on: 1 worker process(es) read the 3 OBJ file(s)" in text


@pytest.mark.parametrize("knob", ["on", "off"])
def test_a_model_swapped_after_the_scene_loaded_is_refused_by_either_reader(tmp_path, knob):
    """The scene's check lets the files through (read_jail.outside remembers them); one is then swapped for a link
    to a copy outside the scene's folders. The cached reader and a worker read through read_jail.read_checked,
    so the swap is refused in one line, cache or not (a worker inherits the checked paths with the fork)."""
    (tmp_path / "outside").mkdir()
    names = _cubes(tmp_path, 3)
    procedural.write_obj(tmp_path / "outside" / "c1.obj", procedural.box(0.51))
    plan = resolve_plan(_scene(tmp_path, names), None, mesh_workers=knob)
    (tmp_path / "c1.obj").unlink()
    (tmp_path / "c1.obj").symlink_to(tmp_path / "outside" / "c1.obj")
    with pytest.raises(UserError) as err:
        _meshes(plan)
    assert "c1.obj" in str(err.value) and "is now a symbolic link" in str(err.value) and "\n" not in str(err.value)


def test_a_large_scene_read_here_writes_no_entries_a_small_one_does(tmp_path, monkeypatch):
    """Read in this process (mesh_workers off), a scene of MIN_FILES OBJ files or more reads the cache but writes
    nothing (10,000 entries from one process cost more than the parses on the H100 host); a smaller one writes."""
    monkeypatch.setattr(plan_meshes, "MIN_FILES", 4)
    names = _cubes(tmp_path, 4)
    _meshes(resolve_plan(_scene(tmp_path, names), None, mesh_workers="off"))
    assert list(obj_cached.folder().glob("*.mesh")) == []
    _meshes(resolve_plan(_scene(tmp_path, names[:3]), None, mesh_workers="off"))
    assert len(list(obj_cached.folder().glob("*.mesh"))) == 3


def test_a_worker_checks_a_path_the_read_rule_never_saw_itself(tmp_path):
    """A bundled scene's model (no read rule: nothing vouched) gets input_file's checks in the worker: a folder
    named like a model is refused in one line, not opened."""
    from wgpurender.core.models import mesh_workers

    (tmp_path / "d.obj").mkdir()
    (entries, blob) = mesh_workers.read_chunk([(tmp_path / "d.obj", False)], None)
    assert entries[0][0] == "refused" and "directory" in entries[0][1] and blob == b""
