"""``w.export`` stays the API's function after it ran (issue 28.12).

The page writer lived in the subpackage ``wgpurender.export``: importing it (inside the first ``w.export(...)``)
made Python bind the subpackage as the package attribute ``export``, so ``w.export`` became a module and a second
call failed with "'module' object is not callable". The subpackage is ``wgpurender.webpage`` now.
"""

from __future__ import annotations

import subprocess
import sys


def test_w_export_is_still_the_function_after_a_call(tmp_path):
    code = f"""
import wgpurender as w
first = w.export("triangle", {str(tmp_path / 'a')!r}, size=(16, 12))
assert callable(w.export) and w.export.__module__ == "wgpurender.api", w.export
second = w.export("triangle", {str(tmp_path / 'b')!r}, size=(16, 12))
print(first.name, second.name)
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["index.html", "index.html"]
    assert (tmp_path / "a" / "data.js").is_file() and (tmp_path / "b" / "data.js").is_file()


def test_no_subpackage_is_named_like_an_api_function():
    from pathlib import Path

    import wgpurender

    package = Path(wgpurender.__file__).parent
    for name in wgpurender._API:
        assert not (package / name).exists() and not (package / f"{name}.py").exists(), name
