"""pycparser imported only when cffi parses C text (wgpurender/wgpu_path/device/parser_on_demand.py, issue 31.5).

Fresh processes sharing a private $XDG_CACHE_HOME: the first parses wgpu.h (through the stand-in, which then
imports the real pycparser) and saves the parse; the second restores it, makes a device and renders without
importing pycparser, then parses a C type the fast path does not know, which imports it on demand. The version
read from pycparser's source is the package's own.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
CHILD = r"""
import json, sys
from wgpurender.wgpu_path.device import cdef_cache, parser_on_demand
from_source = parser_on_demand.version() if "pycparser" not in sys.modules else None
from wgpurender.wgpu_path.device.context import get_context
from wgpurender.wgpu_path.render import render_stage

pixels = render_stage("triangle", (8, 6), ctx=get_context()).pixels
before = "pycparser" in sys.modules
from wgpu.backends.wgpu_native._ffi import ffi
size = ffi.sizeof("int(*[5])[3]")  # an array of 5 pointers: a declaration for the real parser
print(json.dumps({"status": cdef_cache.status, "before": before, "after": "pycparser" in sys.modules,
                  "size": size, "pointer": ffi.sizeof("void *"), "lit": int((pixels[..., 3] > 0).sum()),
                  "version": from_source, "real": sys.modules["pycparser"].__version__}))
"""


def _child(env: dict) -> dict:
    path = os.pathsep.join([str(REPO), *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))])
    out = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=180,
                         env=dict(env, PYTHONPATH=path))
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_pycparser_is_imported_only_to_parse(tmp_path):
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path), WGPURENDER_VALIDATION="0")
    first, second = _child(env), _child(env)
    assert first["status"] == "parsed and saved" and first["before"]  # a real parse needs the real pycparser
    assert second["status"] == "restored" and not second["before"]  # restored: a device and a frame without it
    for run in (first, second):
        assert run["after"] and run["size"] == 5 * run["pointer"]  # parsed on demand, and right
        assert run["lit"] == 48  # the triangle stage clears to an opaque colour: every pixel drawn
        assert run["version"] == run["real"]  # read from its source before it was imported
