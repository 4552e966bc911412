"""The mesh workers as fresh interpreters of our own worker module (core/models/worker_processes.py,
core/models/mesh_worker_main.py; issue 31.3): never forks of the renderer, booted while a large scene is checked
(as many as the plan's rule gives for the TOML's OBJ file names), the ones booted are the ones that read, ended
when the plan reads here or when the reading ends, and no worker outlives a parent that was killed."""

from __future__ import annotations

import os
import subprocess
import sys
import time

import pytest
from helpers import same_mesh as _same

from wgpurender.core.errors import UserError
from wgpurender.core.models import procedural, worker_processes
from wgpurender.core.models.mesh import load_mesh
from wgpurender.core.plan import mesh_loading, resolve_plan
from wgpurender.core.plan.meshes import PlanMeshes
from wgpurender.core.scene import load_scene

pytestmark = pytest.mark.skipif(not mesh_loading.can_fork(), reason="worker processes run on Linux here")

CAMERA = "[camera]\neye = [0.0, 0.0, 30.0]\ntarget = [0.0, 0.0, 0.0]\n\n"
N = mesh_loading.MIN_FILES  # the fewest files the auto rule gives workers for


@pytest.fixture(autouse=True)
def own_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    yield
    worker_processes.drop_booted()


def _scene(folder, names):
    text = CAMERA + "".join(f'[[models]]\npath = "{n}"\n\n' for n in names)
    (folder / "s.toml").write_text(text)
    return folder / "s.toml"


def _cubes(folder, n):
    for k in range(n):
        procedural.write_obj(folder / f"c{k}.obj", procedural.box(0.5 + 0.001 * k))
    return [f"c{k}.obj" for k in range(n)]


def _running(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rpartition(")")[2].split()[0] != "Z"
    except FileNotFoundError:
        return False


def _gone(pids, seconds=30.0) -> bool:
    deadline = time.monotonic() + seconds
    while any(_running(pid) for pid in pids):
        if time.monotonic() > deadline:
            return False
        time.sleep(0.05)
    return True


def _command(pid: int) -> list[str]:
    with open(f"/proc/{pid}/cmdline", "rb") as f:
        return f.read().decode().split("\0")[:-1]


def test_a_worker_is_a_fresh_interpreter_of_our_worker_module_not_a_fork():
    pool = worker_processes.Workers(1)
    try:
        command = _command(pool.procs[0].pid)
        assert command[1:] == ["-m", "wgpurender.core.models.mesh_worker_main"]
        assert os.path.realpath(command[0]) == os.path.realpath(sys.executable)
    finally:
        pool.end()
    assert not _running(pool.procs[0].pid)


def test_a_large_scene_boots_as_many_workers_as_the_rule_gives_while_it_is_checked(tmp_path):
    """The scene's files do not exist: its check refuses it, after the workers were started from its TOML."""
    wanted, _ = mesh_loading.resolve_mesh_workers("auto", N)
    with pytest.raises(UserError, match="c0.obj"):
        load_scene(_scene(tmp_path, [f"c{k}.obj" for k in range(N)]))
    booted = worker_processes._booted
    assert (0 if booted is None else len(booted.procs)) == wanted
    if booted is not None:
        pids = [p.pid for p in booted.procs]
        assert all(_command(pid)[-1] == worker_processes.MODULE for pid in pids)
        worker_processes.drop_booted()
        assert worker_processes._booted is None and _gone(pids, 5)


def test_one_file_named_many_times_boots_no_workers(tmp_path):
    with pytest.raises(UserError, match="c0.obj"):
        load_scene(_scene(tmp_path, ["c0.obj"] * N))
    assert worker_processes._booted is None


@pytest.mark.skipif(mesh_loading.usable_cores() < 2, reason="the auto rule gives no workers on one core")
def test_the_workers_booted_ahead_are_the_ones_that_read(tmp_path, monkeypatch):
    names = _cubes(tmp_path, N)
    scene = load_scene(_scene(tmp_path, names))
    booted = [p.pid for p in worker_processes._booted.procs]
    served = []
    real = worker_processes.Workers.read
    monkeypatch.setattr(worker_processes.Workers, "read",
                        lambda self, *a: served.extend(p.pid for p in self.procs) or real(self, *a))
    plan = resolve_plan(scene, None)
    meshes = PlanMeshes(plan)
    got = [meshes.mesh(d.mesh_key) for d in plan.scene_pass.draws]
    assert served == booted and _gone(booted, 5)  # ended with the reading
    for mesh, name in zip(got[::37], names[::37], strict=True):
        _same(mesh, load_mesh(tmp_path / name, generate_tangents=False))


def test_a_plan_that_reads_here_ends_the_workers_booted_ahead(tmp_path):
    names = _cubes(tmp_path, N)
    scene = load_scene(_scene(tmp_path, names))
    if worker_processes._booted is None:
        pytest.skip("the auto rule gave no workers on this machine")
    pids = [p.pid for p in worker_processes._booted.procs]
    PlanMeshes(resolve_plan(scene, None, mesh_workers="off"))
    assert worker_processes._booted is None and _gone(pids, 5)


def test_no_worker_outlives_a_killed_parent():
    """The parent is killed (no finalizer runs): each worker sees its stdin end and ends, booted or reading."""
    code = ("import os, signal; from wgpurender.core.models import worker_processes as w\n"
            "pool = w.Workers(2); print(' '.join(str(p.pid) for p in pool.procs), flush=True)\n"
            "os.kill(os.getpid(), signal.SIGKILL)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    pids = [int(pid) for pid in done.stdout.split()]
    assert len(pids) == 2 and done.returncode == -9
    assert _gone(pids), "a worker outlived its killed parent"
