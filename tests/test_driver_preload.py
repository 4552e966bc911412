"""The Vulkan drivers' libraries loaded on a thread before wgpu-py is imported (issue 31.5): which ones, and that
a process that preloads them still draws the same image.

Which libraries: the manifests the Vulkan loader reads (its documented variables and folders), built here in a
temporary folder; the expected names come from the manifests' text written by the test.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wgpurender.wgpu_path.device import driver_preload as dp

REPO = Path(__file__).resolve().parent.parent


def _manifest(folder: Path, name: str, library_path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    path.write_text(json.dumps({"file_format_version": "1.0.0", "ICD": {"library_path": library_path}}))
    return path


def test_the_named_manifests_give_their_libraries_in_order_with_relative_paths_from_the_manifest(tmp_path):
    a = _manifest(tmp_path / "a", "a.json", "/opt/x/libvulkan_a.so")
    b = _manifest(tmp_path / "b", "b.json", "./lib/libvulkan_b.so")
    _manifest(tmp_path / "c", "c.json", "libvulkan_c.so")
    _manifest(tmp_path / "c", "d.json", "/opt/x/libvulkan_a.so")  # the same library twice: loaded once
    env = {"VK_DRIVER_FILES": os.pathsep.join([str(a), str(b), str(tmp_path / "c")])}
    assert dp.libraries(env) == [dp.LOADER, "/opt/x/libvulkan_a.so", str(tmp_path / "b" / "lib/libvulkan_b.so"),
                                 "libvulkan_c.so"]


def test_the_older_variable_and_the_added_files_count_and_named_files_replace_the_search(tmp_path):
    a = _manifest(tmp_path, "a.json", "/l/a.so")
    added = _manifest(tmp_path / "add", "x.json", "/l/x.so")
    _manifest(tmp_path / "home" / ".local/share/vulkan/icd.d", "h.json", "/l/h.so")
    base = {"HOME": str(tmp_path / "home"), "XDG_DATA_DIRS": str(tmp_path / "none"),
            "XDG_CONFIG_DIRS": str(tmp_path / "none")}
    assert dp.libraries({**base, "VK_ICD_FILENAMES": str(a)}) == [dp.LOADER, "/l/a.so"]
    assert dp.libraries({**base, "VK_DRIVER_FILES": str(a), "VK_ADD_DRIVER_FILES": str(added)}) == [
        dp.LOADER, "/l/a.so", "/l/x.so"]
    searched = dp.libraries({**base, "VK_ADD_DRIVER_FILES": str(added)})
    assert searched[:3] == [dp.LOADER, "/l/x.so", "/l/h.so"]  # the added file, then the user's data folder


def test_the_search_reads_the_xdg_folders(tmp_path):
    _manifest(tmp_path / "cfg/vulkan/icd.d", "c.json", "/l/c.so")
    _manifest(tmp_path / "data/vulkan/icd.d", "d.json", "/l/d.so")
    env = {"HOME": str(tmp_path / "nohome"), "XDG_CONFIG_DIRS": str(tmp_path / "cfg"),
           "XDG_DATA_DIRS": str(tmp_path / "data")}
    found = dp.libraries(env)
    assert found[:3] == [dp.LOADER, "/l/c.so", "/l/d.so"]


def test_unreadable_manifests_are_skipped_and_the_loaders_filters_preload_nothing(tmp_path):
    good = _manifest(tmp_path, "good.json", "/l/good.so")
    (tmp_path / "bad.json").write_text("{not json")
    _manifest(tmp_path, "empty.json", "")
    (tmp_path / "nolib.json").write_text(json.dumps({"ICD": {}}))
    env = {"VK_DRIVER_FILES": os.pathsep.join([str(tmp_path), str(tmp_path / "missing.json")])}
    assert dp.libraries(env) == [dp.LOADER, "/l/good.so"]
    assert dp.library(good) == "/l/good.so"
    for name in dp.FILTERS:
        assert dp.libraries({**env, name: "*lvp*"}) == []


@pytest.mark.parametrize(("backend", "env", "wants"), [
    (None, {}, True), ("Vulkan", {}, True), ("auto", {}, True), ("OpenGL", {}, False),
    (None, {dp.BACKEND_ENV: "opengl"}, False), (None, {dp.BACKEND_ENV: "VULKAN"}, True),
    ("Vulkan", {dp.BACKEND_ENV: "opengl"}, True)])
def test_only_a_request_that_may_use_vulkan_preloads(backend, env, wants):
    assert dp.wants_vulkan(backend, env) is wants


def _python(code: str, *args: str) -> str:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(REPO), *filter(None, [os.environ.get("PYTHONPATH")])]),
               WGPURENDER_VALIDATION="0")
    out = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=120, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.strip()


RENDER = ("import wgpurender as w\n"
          "np.save(sys.argv[1], w.render('3d', size=(64, 48)).pixels)\n")


def test_start_loads_the_drivers_before_wgpu_is_imported_and_the_image_is_the_same(tmp_path):
    """In a fresh process: after start() and its thread, every library that loaded is in the process's maps and
    wgpu-py is not imported yet; its render equals that of a process whose preload does nothing."""
    # A manifest may name its library bare (NVIDIA's "libGLX_nvidia.so.0", found by dlopen's search, mapped as
    # .../libGLX_nvidia.so.580.159.04): such a handle counts when a mapped file's name starts with its stem ".so".
    code = ("import os, sys, numpy as np\n"
            "from wgpurender.wgpu_path.device import driver_preload as dp\n"
            "dp.start(); dp.join()\n"
            "maps = open('/proc/self/maps').read()\n"
            "mapped = {os.path.basename(line.split()[-1]) for line in maps.splitlines() if '/' in line}\n"
            "def found(name):\n"
            "    if '/' in name: return name in maps\n"
            "    stem = name.split('.so')[0] + '.so'\n"
            "    return any(m.startswith(stem) for m in mapped)\n"
            "print(sum(1 for h in dp._loaded if found(h._name)), len(dp._loaded), 'wgpu' in sys.modules)\n" + RENDER)
    loaded, handles, wgpu_imported = _python(code, str(tmp_path / "pre.npy")).split()
    assert int(handles) >= 2 and loaded == handles and wgpu_imported == "False"  # the loader and a driver at least
    none = ("import sys, numpy as np\n"
            "from wgpurender.wgpu_path.device import driver_preload as dp\n"
            "dp.start = lambda backend=None: None\n" + RENDER)
    _python(none, str(tmp_path / "none.npy"))
    pre, plain = np.load(tmp_path / "pre.npy"), np.load(tmp_path / "none.npy")
    assert pre.shape == (48, 64, 4) and np.array_equal(pre, plain)
    assert len(np.unique(pre.reshape(-1, 4), axis=0)) > 2  # cubes drawn, not one colour


def test_a_backend_already_spelled_as_the_adapter_spells_it_needs_no_checks_module_before_the_thread():
    """requested_backend's fast path: the default (and any canonical name) is taken as is, so core.checks is not
    imported before the device thread starts; another spelling still goes through checks.backend."""
    code = ("import sys\n"
            "from wgpurender.wgpu_path.device import context as c\n"
            "print(c.requested_backend(), c.requested_backend('auto'), 'wgpurender.core.checks' in sys.modules, "
            "c.requested_backend('vulkan'), 'wgpurender.core.checks' in sys.modules)\n")
    env_free = {k: v for k, v in os.environ.items() if k != dp.BACKEND_ENV}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                         env={**env_free, "PYTHONPATH": os.pathsep.join([str(REPO), env_free.get("PYTHONPATH", "")])})
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split() == ["Vulkan", "auto", "False", "Vulkan", "True"]


def test_start_runs_once_and_not_for_another_backend(monkeypatch):
    monkeypatch.setattr(dp, "_started", [])
    monkeypatch.setattr(dp, "_load", lambda: None)  # the thread without the loading
    monkeypatch.delenv(dp.BACKEND_ENV, raising=False)
    dp.start("OpenGL")
    assert dp._started == []
    dp.start()
    dp.start("Vulkan")
    dp.join()
    assert len(dp._started) == 1


def test_the_apis_render_and_the_startup_childs_wgpu_run_preload_and_the_comparison_row_does_not():
    code = ("import sys\n"
            "from wgpurender.wgpu_path.device import driver_preload as dp\n"
            "{call}\n"
            "print(len(dp._started))\n")
    calls = {"import wgpurender as w; w.render('triangle', size=(32, 24))": "1",
             "from wgpurender.bench.startup_child import child; child('wgpu', 'triangle', (32, 24), 0.0)": "1",
             "from wgpurender.bench.startup_child import main; main(0.0, ['wgpu', 'triangle', '32x24'])": "1",
             "from wgpurender.bench.startup_child import main; main(0.0, ['wgpu', 'triangle', '32x24', 'no-preload'])":
                 "0"}
    for call, started in calls.items():
        assert _python(code.format(call=call)).splitlines()[-1] == started, call


def test_a_named_place_that_cannot_be_examined_is_skipped_not_a_traceback_on_the_thread(tmp_path):
    """A name longer than the system takes (ENAMETOOLONG, which pathlib's is_dir does not swallow) raised on the
    preload thread, which printed a traceback into the output of `wgpurender render`."""
    good = _manifest(tmp_path, "good.json", "/l/good.so")
    too_long = tmp_path / ("a" * (os.pathconf(str(tmp_path), "PC_NAME_MAX") + 1))
    env = {"VK_DRIVER_FILES": os.pathsep.join([str(too_long), str(good)])}
    assert dp.libraries(env) == [dp.LOADER, "/l/good.so"]
