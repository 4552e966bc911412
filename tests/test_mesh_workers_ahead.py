"""The workers handed the plan's OBJ files ahead (PlanMeshes.start_reading in core/plan/meshes.py,
Reading in core/models/mesh_workers.py): they read while the scene pass makes what needs no mesh, and the meshes, the
images and the one-line refusal are those of a read started where the meshes are first asked for."""

from __future__ import annotations

import gc
import time

import numpy as np
import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.models import mesh_workers, obj_cached, procedural
from wgpurender.core.plan import mesh_loading, resolve_plan
from wgpurender.core.plan.meshes import PlanMeshes

pytestmark = pytest.mark.skipif(not mesh_loading.can_fork(), reason="worker processes need fork (Linux)")

CAMERA = ("[camera]\neye = [0.0, 0.0, 6.0]\ntarget = [0.0, 0.0, 0.0]\n\n"
          '[[lights]]\ntype = "directional"\ndirection = [-0.5, -0.6, -1.0]\nintensity = 3.0\n\n')
NAN_CUBE = "v nan 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n"


@pytest.fixture(autouse=True)
def own_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))


def _scene(folder, names):
    text = CAMERA + "".join(f'[[models]]\npath = "{n}"\n'
                            f'transform = {{ translate = [{k % 5 - 2}, {k // 5 - 1}, 0] }}\n\n'
                            for k, n in enumerate(names)) + "[render]\nsize = [64, 48]\nmsaa = 1\n"
    path = folder / "s.toml"
    path.write_text(text)
    return path


def _cubes(folder, n):
    for k in range(n):
        procedural.write_obj(folder / f"c{k}.obj", procedural.box(0.5 + 0.01 * k))  # distinct files
    return [f"c{k}.obj" for k in range(n)]


def test_the_workers_read_before_the_first_mesh_is_asked_for(tmp_path):
    scene = _scene(tmp_path, _cubes(tmp_path, 9))
    on, off = (resolve_plan(scene, None, mesh_workers=k) for k in ("on", "off"))
    meshes = PlanMeshes(on)
    meshes.start_reading()
    deadline = time.monotonic() + 30
    while not list(obj_cached.folder().glob("*.meshes")):  # the worker stores the chunk it parsed, unasked
        assert time.monotonic() < deadline, "the workers read nothing before the first mesh was asked for"
        time.sleep(0.02)
    here = PlanMeshes(off)
    for draw in on.scene_pass.draws:
        got, want = meshes.mesh(draw.mesh_key), here.mesh(draw.mesh_key)
        assert np.array_equal(got.positions, want.positions) and np.array_equal(got.indices, want.indices)
        assert np.array_equal(got.tangents if got.tangents is not None else [], want.tangents
                              if want.tangents is not None else [])


def test_without_workers_nothing_starts_ahead(tmp_path):
    scene = _scene(tmp_path, _cubes(tmp_path, 3))
    meshes = PlanMeshes(resolve_plan(scene, None, mesh_workers="off"))
    meshes.start_reading()
    assert meshes._reading is None and not list(obj_cached.folder().glob("*.mesh*"))


def _running(pid: int) -> bool:
    """Whether process ``pid`` still runs (a zombie has ended): read from /proc, not through the Process object,
    whose poll answers "alive" forever once the executor's own thread has reaped the child."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rpartition(")")[2].split()[0] != "Z"
    except FileNotFoundError:
        return False


def test_a_reading_never_finished_ends_its_workers(tmp_path):
    names = _cubes(tmp_path, 2)
    reading = mesh_workers.Reading([(tmp_path / n, False) for n in names], 1, None)
    pids = [p.pid for p in reading.pool._processes.values()]
    assert pids and all(_running(pid) for pid in pids)
    del reading
    gc.collect()
    deadline = time.monotonic() + 30
    while any(_running(pid) for pid in pids):
        assert time.monotonic() < deadline, "an unfinished reading left its workers running"
        time.sleep(0.05)


def test_the_renderer_draws_the_same_image_with_the_workers_ahead(tmp_path, ctx, monkeypatch):
    from wgpurender.wgpu_path.scene import load_renderer, scene_pass
    from wgpurender.wgpu_path.scene.frame import render_frame

    scene = _scene(tmp_path, _cubes(tmp_path, 9))
    images, ahead = [], []
    real = scene_pass.ScenePassRenderer._setup_materials

    def watched(self):  # are the workers reading while the pipelines and material groups are made?
        ahead.append(self.resources.meshes._reading is not None)
        return real(self)

    monkeypatch.setattr(scene_pass.ScenePassRenderer, "_setup_materials", watched)
    for knob in ("on", "off"):
        renderer = load_renderer(scene, ctx, knobs={"mesh_workers": knob})
        assert renderer.plan.mesh_workers == (1 if knob == "on" else 0)
        images.append(np.asarray(render_frame(ctx, renderer, renderer.create_output())[0]))
    assert ahead == [True, False]
    assert np.array_equal(images[0], images[1])
    assert (images[0][..., :3].max(axis=2) > 0).sum() > 100  # the cubes are drawn


def test_a_refused_file_is_the_error_when_the_set_up_beside_the_workers_fails_too(tmp_path, ctx, monkeypatch):
    from wgpurender.wgpu_path.scene import load_renderer, scene_pass

    names = _cubes(tmp_path, 4)
    (tmp_path / "bad.obj").write_text(NAN_CUBE)
    scene = _scene(tmp_path, [*names[:2], "bad.obj", *names[2:]])

    def broken(self):
        raise RuntimeError("the set-up beside the workers failed")

    monkeypatch.setattr(scene_pass.ScenePassRenderer, "_setup_materials", broken)
    with pytest.raises(UserError) as err:
        load_renderer(scene, ctx, knobs={"mesh_workers": "on"})
    assert "bad.obj" in str(err.value) and "NaN" in str(err.value) and "\n" not in str(err.value)
    (tmp_path / "bad.obj").unlink()
    scene = _scene(tmp_path, names)
    with pytest.raises(RuntimeError, match="beside the workers"):  # with every file good, its own error
        load_renderer(scene, ctx, knobs={"mesh_workers": "on"})
