"""What the benchmark's processes import before they time anything (issue 31.5 and 31.8).

- The startup family's raw child times the raw path's first pixel from process start: it must not import wgpu-py
  (bench/frames.py did, through bench/encoder.py, adding wgpu-py's import to the raw path's time).
- With $WGPURENDER_BINDING=dawn, a bench module's ``import wgpu`` must get Dawn's wgpu: the binding is installed
  when the bench package loads. Before, ``python -m wgpurender.bench.startup`` (the startup child) and the
  benchmark scripts imported wgpu-native first and stopped on "set after wgpu-native was loaded". Dawn needs a
  GPU, so a stand-in ``wgpudawn`` is used here: its ``install_as_wgpu`` marks the ``wgpu`` module it installs, and
  the bench module's ``wgpu`` must carry the mark.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def _python(code: str, **env) -> str:
    """Run ``code`` in a fresh interpreter with ``path`` first on PYTHONPATH, the caller's entries kept after it
    (a machine whose packages live on PYTHONPATH, as the GPU machine's, must still find wgpu and vulkan)."""
    path = [*env.pop("path", [str(REPO)]), *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))]
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(path), **env))
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.strip()


def test_the_raw_startup_child_imports_no_wgpu():
    """The raw child's whole run (imports, context, a stage's first two frames), then: was wgpu-py loaded?"""
    code = ("import sys, time\nimport wgpurender.bench.startup_child as s\n"
            "out = s.child('raw', 'triangle', (32, 24), time.perf_counter())\n"
            "print(out['total_ms'] > 0, 'wgpu' in sys.modules)")
    assert _python(code, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp")) == "True False"


def test_a_bench_module_gets_dawns_wgpu_when_dawn_is_asked_for(tmp_path):
    (tmp_path / "wgpudawn.py").write_text(  # marks the wgpu it installs (the real one here: no GPU needed)
        "def install_as_wgpu():\n"
        "    import wgpu\n"
        "    wgpu.STAND_IN = True\n")
    code = ("import wgpurender.bench.startup\nimport wgpurender.bench.encoder as e\n"
            "print(getattr(e.wgpu, 'STAND_IN', False))")
    assert _python(code, path=[str(REPO), str(tmp_path)], WGPURENDER_BINDING="dawn") == "True"
