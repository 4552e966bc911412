"""On-disk caches serve only whole entries written for the key asked (issue 28.8).

Before: the SPIR-V cache served any file at its name (an empty one crashed vkCreateShaderModule's caller, an
altered one was handed to the driver), the VkPipelineCache's bytes went to the driver unchecked, the cffi parse
was a pickle (tests/test_cdef_cache.py), and a bandwidth record of another shape was a traceback in
``render --explain``. Every cache now stores a sealed entry (core/files/cache_entry.py): empty, truncated, altered
(one flipped byte) and wrong-key entries are each a miss, and what is computed again is the same.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from wgpurender.core.files import bandwidth, cache_entry


def _flip(data: bytes) -> bytes:
    k = len(data) - 3  # in the payload, past the header
    return data[:k] + bytes([data[k] ^ 0x01]) + data[k + 1:]


DAMAGE = {
    "empty": lambda data, key: b"",
    "truncated": lambda data, key: data[:-4],
    "header only": lambda data, key: data[:cache_entry.HEADER],
    "flipped byte": lambda data, key: _flip(data),
    "flipped key hash": lambda data, key: data[:len(cache_entry.MAGIC)] + bytes([data[len(cache_entry.MAGIC)] ^ 1])
    + data[len(cache_entry.MAGIC) + 1:],
    "wrong key": lambda data, key: cache_entry.seal(key + " of another version", data[cache_entry.HEADER:]),
    "raw payload": lambda data, key: data[cache_entry.HEADER:],  # what the old caches stored
}


@pytest.mark.parametrize("damage", sorted(DAMAGE))
def test_a_damaged_entry_is_a_miss(tmp_path, damage):
    path, key, payload = tmp_path / "entry", "key 1", bytes(range(256)) * 8
    assert cache_entry.write_entry(path, key, payload) and cache_entry.read_entry(path, key) == payload
    path.write_bytes(DAMAGE[damage](path.read_bytes(), key))
    assert cache_entry.read_entry(path, key) is None


def test_special_files_and_links_are_misses(tmp_path):
    real = tmp_path / "real"
    cache_entry.write_entry(real, "k", b"payload")
    (tmp_path / "link").symlink_to(real)
    os.mkfifo(tmp_path / "fifo")
    assert cache_entry.read_entry(tmp_path / "link", "k") is None  # a link planted to another file
    assert cache_entry.read_entry(tmp_path / "fifo", "k") is None  # never opened (would block)
    assert cache_entry.read_entry(tmp_path / "absent", "k") is None


def test_a_link_planted_at_the_temp_name_is_never_written_through(tmp_path):
    """Whoever can write the cache folder can guess the temp name (``.NAME.PID.tmp``) and plant a link there to a
    file of the user's: the write must not follow it (found by issue 28's independent fuzz: O_TRUNC without
    O_EXCL truncated and overwrote the link's target)."""
    users = tmp_path / "users-file.txt"
    users.write_text("the user's own work\n")
    cache = tmp_path / "cache"
    cache.mkdir()
    entry = cache / "entry.spv"
    (cache / f".{entry.name}.{os.getpid()}.tmp").symlink_to(users)
    assert cache_entry.write_entry(entry, "k", b"payload")  # the planted link removed, not followed
    assert users.read_text() == "the user's own work\n"
    assert cache_entry.read_entry(entry, "k") == b"payload"


@pytest.fixture
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    from wgpurender.raw_path.device import shaders as glsl

    monkeypatch.setattr(glsl, "_MEMORY_CACHE", {})
    return tmp_path / "cache" / "wgpurender"


@pytest.mark.parametrize("damage", sorted(DAMAGE))
def test_a_damaged_spirv_entry_is_compiled_again_to_the_same_module(private_cache, monkeypatch, damage):
    from wgpurender.raw_path.device import shaders as glsl

    path = glsl.glsl_path("color.frag")
    fresh = glsl.compile_glsl(path)
    assert fresh[:4] == b"\x03\x02\x23\x07"
    (entry,) = (private_cache / "spirv").glob("*.spv")
    key = b"\0".join([b"spirv", b".frag", *(a.encode() for a in glsl.GLSLC_ARGS), path.read_bytes()])
    entry.write_bytes(DAMAGE[damage](entry.read_bytes(), key.decode()))
    calls = []
    real = glsl._run_glslc
    monkeypatch.setattr(glsl, "_run_glslc", lambda *a: calls.append(a) or real(*a))
    assert glsl.compile_glsl(path) == fresh and len(calls) == 1  # a miss: glslc ran, the same SPIR-V
    assert glsl.compile_glsl(path) == fresh and len(calls) == 1  # and the entry was written whole again


CHILD = """
import sys
import wgpurender as w
w.reference("textured", size=(24, 18)).save(sys.argv[1])
"""


def test_a_damaged_pipeline_cache_is_a_miss_and_the_same_image(tmp_path):
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}

    def run(name: str) -> np.ndarray:
        done = subprocess.run([sys.executable, "-c", CHILD, str(tmp_path / name)], env=env, capture_output=True,
                              text=True, timeout=300)
        assert done.returncode == 0 and not done.stderr.strip(), done.stderr[-2000:]
        return np.asarray(Image.open(tmp_path / name))

    first = run("first.png")
    (entry,) = (tmp_path / "cache" / "wgpurender").glob("vk-pipeline-cache-*.bin")
    assert entry.read_bytes().startswith(cache_entry.MAGIC)
    entry.write_bytes(_flip(entry.read_bytes()))
    assert np.array_equal(run("flipped.png"), first)
    entry.write_bytes(entry.read_bytes()[: cache_entry.HEADER + 10])
    assert np.array_equal(run("truncated.png"), first)
    assert entry.read_bytes().startswith(cache_entry.MAGIC) and len(entry.read_bytes()) > cache_entry.HEADER + 10


GOOD = {"ms": 0.08, "mb": 99.5, "copy_ms": 0.04, "size": "3840x2160", "date": "2026-11-24", "command": "bench"}
SHAPES = {
    "a list": [], "a number": 5, "adapter a list": {"GPU": []}, "pass a string": {"GPU": {"k": "fast"}},
    "ms a string": {"GPU": {"k": {**GOOD, "ms": "0.08"}}}, "ms a bool": {"GPU": {"k": {**GOOD, "ms": True}}},
    "a field missing": {"GPU": {"k": {n: v for n, v in GOOD.items() if n != "copy_ms"}}},
    "an extra field": {"GPU": {"k": {**GOOD, "gbps": 1.0}}}, "ms zero": {"GPU": {"k": {**GOOD, "ms": 0}}},
    "mb nan": {"GPU": {"k": {**GOOD, "mb": float("nan")}}}, "size a number": {"GPU": {"k": {**GOOD, "size": 4}}},
}


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_a_bandwidth_record_of_the_wrong_shape_is_not_measured(tmp_path, monkeypatch, shape):
    record = tmp_path / "bandwidth.json"
    monkeypatch.setenv(bandwidth.RECORD_ENV, str(record))
    record.write_text(json.dumps(SHAPES[shape]))
    assert bandwidth.lookup("GPU", "k") is None
    bandwidth.save("GPU", {"k": bandwidth.PassRecord(**GOOD)})  # a save replaces what it cannot read
    assert bandwidth.lookup("GPU", "k") == bandwidth.PassRecord(**GOOD)


def test_the_explain_text_says_not_measured_for_a_bad_record(tmp_path):
    record = tmp_path / "bandwidth.json"
    record.write_text(json.dumps({"llvmpipe": ["not", "a", "record"]}))
    env = {**os.environ, bandwidth.RECORD_ENV: str(record), "XDG_CACHE_HOME": str(tmp_path / "cache")}
    scene = Path(__file__).resolve().parent.parent / "assets" / "scenes" / "final_subpass.toml"
    done = subprocess.run([sys.executable, "-m", "wgpurender", "render", str(scene), "--explain"], env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr[-2000:]
    assert "bandwidth: not measured" in done.stdout


def test_a_relative_cache_home_is_ignored_and_no_cache_lands_in_the_working_folder(tmp_path):
    """The XDG spec: a relative $XDG_CACHE_HOME is invalid and ignored. Taken as it was, `wgpurender render` run in
    a user's folder wrote its wgpu.h parse cache under ./REL/ there (and each cache module had its own copy
    of the rule: wgpu.h's parse, SPIR-V, the bandwidth record, the meshes)."""
    work, home = tmp_path / "work", tmp_path / "home"
    work.mkdir()
    relative = "rel-cache"
    code = ("from wgpurender.core.files import bandwidth, cache_entry\n"
            "from wgpurender.raw_path.device import shaders\n"
            "from wgpurender.wgpu_path.device import cdef_cache\n"
            "import wgpurender as w\n"
            "w.render('triangle', size=(16, 12))\n"
            "print(cache_entry.cache_folder('meshes'), shaders.cache_dir(), cdef_cache.cache_dir(), "
            "bandwidth.record_path())\n")
    env = {k: v for k, v in os.environ.items() if k != bandwidth.RECORD_ENV}
    env.update(XDG_CACHE_HOME=relative, HOME=str(home), WGPURENDER_VALIDATION="0",
               PYTHONPATH=os.pathsep.join([str(Path(__file__).resolve().parent.parent),
                                           *filter(None, [os.environ.get("PYTHONPATH")])]))
    out = subprocess.run([sys.executable, "-c", code], cwd=work, env=env, capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    ours = home / ".cache" / "wgpurender"
    assert out.stdout.split() == [str(ours / "meshes"), str(ours / "spirv"), str(ours), str(ours / "bandwidth.json")]
    assert not (work / relative / "wgpurender").exists(), sorted(p.name for p in (work / relative).rglob("*"))
    assert any(ours.glob("cffi-wgpu-h-*.json")), "the parse was cached where the spec says"


def test_threads_writing_one_entry_at_once_each_write_a_whole_entry(tmp_path):
    """write_entry's temp file was named by the process only: two threads of one process writing the same entry
    shared it, one removed the other's file mid-write, most writes failed and now and then the rename left half
    an entry behind (a miss for every later reader)."""
    import threading

    payloads = [bytes([k]) * (1 << 20) for k in range(8)]
    for trial in range(5):
        path, results = tmp_path / f"entry{trial}", [None] * len(payloads)
        start = threading.Barrier(len(payloads))

        def write(k, path=path, results=results, start=start):
            start.wait()
            results[k] = cache_entry.write_entry(path, "key", payloads[k])

        threads = [threading.Thread(target=write, args=(k,)) for k in range(len(payloads))]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert results == [True] * len(payloads), results
        assert cache_entry.read_entry(path, "key") in payloads  # one writer's whole entry
        assert sorted(p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")) == []  # no temp file left


def test_an_entry_another_user_owns_is_a_miss(tmp_path):
    """The keys are predictable (a file's hash, versions), so anyone who can write the cache folder (a shared or
    lent $XDG_CACHE_HOME) could seal a forged payload under one: an entry owned by another user is not ours."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        pytest.skip("handing a file to another user takes root")
    path = tmp_path / "entry"
    assert cache_entry.write_entry(path, "key", b"payload")
    assert cache_entry.read_entry(path, "key") == b"payload"
    os.chown(path, os.geteuid() + 4242, -1)
    assert cache_entry.read_entry(path, "key") is None


def test_without_a_home_the_caches_use_a_private_folder_not_a_traceback(tmp_path):
    """No $HOME and no account entry for the user (a container run with --user N): Path.home() raised
    RuntimeError inside `wgpurender render` (the wgpu.h parse cache looks its folder up at import). The account
    lookup is made to fail here as it fails for such a user; the render must succeed and leave nothing behind."""
    code = ("import os, pwd, stat, tempfile\n"
            "def nobody(uid):\n"
            "    raise KeyError(uid)\n"
            "pwd.getpwuid = nobody\n"
            "import wgpurender as w\n"
            "from wgpurender.core.files import cache_entry\n"
            "img = w.render('triangle', size=(16, 12))\n"
            "root = cache_entry.cache_root()\n"
            "assert root == cache_entry.cache_root() and root.parent.parent == __import__('pathlib').Path("
            "tempfile.gettempdir()), root\n"
            "assert stat.S_IMODE(os.stat(root.parent).st_mode) == 0o700\n"
            "print(root.parent, img.pixels.shape)\n")
    env = {k: v for k, v in os.environ.items() if k not in ("HOME", "XDG_CACHE_HOME")}
    env.update(WGPURENDER_VALIDATION="0", TMPDIR=str(tmp_path),
               PYTHONPATH=os.pathsep.join([str(Path(__file__).resolve().parent.parent),
                                           *filter(None, [os.environ.get("PYTHONPATH")])]))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and "Traceback" not in out.stderr, out.stderr[-2000:]
    folder, shape = out.stdout.split(maxsplit=1)
    assert shape.strip() == "(12, 16, 4)" and Path(folder).parent == tmp_path
    assert not Path(folder).exists(), "the private folder is removed at exit"
