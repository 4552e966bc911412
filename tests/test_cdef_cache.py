"""wgpu.h's parse cached between processes (wgpurender/wgpu_path/device/cdef_cache.py, issue 22.5) gives cffi the same
declarations as a real parse, and a context that renders.

Two fresh processes share a private $XDG_CACHE_HOME: the first parses the header (and saves the parse), the
second restores it. Each prints every declaration of cffi's parser (its C type name and qualifiers) and every
integer constant, and renders a 4x4 clear whose pixels are checked here. No timing is asserted.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
CHILD = r"""
import json
from wgpurender.wgpu_path.device import cdef_cache
from wgpurender.wgpu_path.device.context import get_context
from wgpurender.wgpu_path.device.targets import create_target, read_texture

ctx = get_context()
from wgpu.backends.wgpu_native._ffi import ffi

def name(v):
    return [v[0]._get_c_name(), v[1]] if isinstance(v, tuple) and hasattr(v[0], "_get_c_name") else repr(v)

target = create_target(ctx, (4, 4), "rgba8unorm")
enc = ctx.device.create_command_encoder()
enc.begin_render_pass(color_attachments=[{"view": target.create_view(), "load_op": "clear", "store_op": "store",
                                           "clear_value": (0.0, 1.0, 0.0, 1.0)}]).end()
ctx.queue.submit([enc.finish()])
print(json.dumps({"status": cdef_cache.status, "pixels": read_texture(ctx, target).tolist(),
                  "decl": {k: name(v) for k, v in ffi._parser._declarations.items()},
                  "ints": ffi._parser._int_constants}))
"""


def _run(cache: Path) -> dict:
    path = os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH", "")) if p)  # keep wheels' paths
    env = dict(os.environ, XDG_CACHE_HOME=str(cache), PYTHONPATH=path)
    env.setdefault("XDG_RUNTIME_DIR", "/tmp")
    proc = subprocess.run([sys.executable, "-c", CHILD], env=env, cwd=REPO, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_restored_parse_equals_a_real_parse(tmp_path):
    first, second = _run(tmp_path), _run(tmp_path)
    assert first["status"] == "parsed and saved" and second["status"] == "restored"
    assert len(first["decl"]) > 500 and first["decl"] == second["decl"]
    assert first["ints"] == second["ints"] and len(first["ints"]) > 100
    for run in (first, second):
        assert run["pixels"] == [[[0, 255, 0, 255]] * 4] * 4
    assert len(list((tmp_path / "wgpurender").glob("cffi-wgpu-h-*.json"))) == 1


def _flip(data: bytes) -> bytes:
    middle = len(data) // 2
    return data[:middle] + bytes([data[middle] ^ 0x20]) + data[middle + 1:]


DAMAGE = {  # issue 28.8: each is a miss, parsed again, and the same context
    "empty": lambda data: b"",
    "truncated": lambda data: data[: len(data) - 100],
    "flipped byte": _flip,
    "wrong key": lambda data: __import__("wgpurender.core.files.cache_entry", fromlist=["seal"]).seal(
        "another header", data[__import__("wgpurender.core.files.cache_entry", fromlist=["HEADER"]).HEADER:]),
}


@pytest.mark.parametrize("damage", sorted(DAMAGE))
def test_a_damaged_cache_file_is_parsed_again(tmp_path, damage):
    first = _run(tmp_path)
    (cached,) = (tmp_path / "wgpurender").glob("cffi-wgpu-h-*.json")
    cached.write_bytes(DAMAGE[damage](cached.read_bytes()))
    again = _run(tmp_path)
    assert again["status"] == "parsed and saved" and again["pixels"][0][0] == [0, 255, 0, 255]
    assert again["decl"] == first["decl"]


class _Planted:
    def __init__(self, marker: str) -> None:
        self.marker = marker

    def __reduce__(self):
        return (os.mkdir, (self.marker,))


def test_a_planted_pickle_never_runs(tmp_path):
    """The cache held a pickle, loaded at every start: a file planted there ran code as the user. Whatever is
    planted (the old pickle name, or a pickle under the new name) is never unpickled."""
    import pickle

    marker = tmp_path / "ran"
    first = _run(tmp_path)
    (cached,) = (tmp_path / "wgpurender").glob("cffi-wgpu-h-*.json")
    planted = pickle.dumps({"_declarations": _Planted(str(marker))})
    cached.write_bytes(planted)
    cached.with_suffix(".pickle").write_bytes(planted)
    again = _run(tmp_path)
    assert not marker.exists() and again["decl"] == first["decl"]
