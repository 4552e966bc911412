"""The wheel stands alone: shaders_glsl/variants.txt lists every GLSL variant the raw path compiles for the
bundled course (every stage and scene, as `wgpurender reference` draws them), so the SPIR-V setup.py compiles into
the wheel covers it (a venv without glslc: tests/test_wheel.py); a shipped file is used only for the source whose
hash names it.

    python tests/test_spirv_shipped.py   # rewrites shaders_glsl/variants.txt from what the raw path compiles
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from wgpurender.core.shaders.spirv_names import VARIANTS_FILE, read_variants, spirv_name

REPO = Path(__file__).resolve().parent.parent
RECORD = """
import json, sys
from wgpurender.raw_path import render_reference
from wgpurender.raw_path.device import shaders as glsl
from wgpurender.raw_path.stages import all_ref_stages
from wgpurender.core.files.assets import bundled_scene_names, bundled_scene
from wgpurender.core.errors import UserError
seen, real = set(), glsl.compile_glsl
def recording(path, defines=()):
    seen.add((glsl.Path(path).name, tuple(defines)))
    return real(path, defines)
glsl.compile_glsl = recording
for stage in all_ref_stages():
    try:
        render_reference(stage, (32, 24))
    except UserError:
        pass
for name in bundled_scene_names():
    try:
        render_reference(str(bundled_scene(name)), None)
    except UserError as err:
        print("skipped", name, str(err).splitlines()[0], file=sys.stderr)
print(json.dumps(sorted(seen)))
"""


def compiled_variants() -> set[tuple[str, tuple[str, ...]]]:
    """(file, defines) of every glslc compile the raw path asks for across the bundled course, in a fresh process."""
    done = subprocess.run([sys.executable, "-c", RECORD], capture_output=True, text=True, timeout=900,
                          env=dict(os.environ, XDG_CACHE_HOME=os.environ.get("XDG_CACHE_HOME", "/nonexistent")))
    assert done.returncode == 0, done.stderr
    return {(name, tuple(defines)) for name, defines in json.loads(done.stdout.splitlines()[-1])}


def test_variants_txt_covers_every_variant_the_course_compiles(tmp_path, monkeypatch):
    if not __import__("shutil").which("glslc"):
        pytest.skip("glslc is needed to record what the raw path compiles")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    listed = set(read_variants((REPO / "shaders_glsl" / VARIANTS_FILE).read_text()))
    missing = compiled_variants() - listed
    assert not missing, f"add to shaders_glsl/{VARIANTS_FILE} (python tests/test_spirv_shipped.py): {sorted(missing)}"


SHIPPED = b"\x03\x02\x23\x07" + b"shipped module words".ljust(28, b".")  # a SPIR-V module's shape


def test_a_shipped_file_is_used_only_for_its_own_source(tmp_path, monkeypatch):
    """glslc absent: a file named for this source is loaded; after an edit of the source it is not (one line)."""
    from wgpurender.core.errors import UserError
    from wgpurender.raw_path.device import shaders as glsl

    shipped = tmp_path / "spirv"
    shipped.mkdir()
    source = tmp_path / "color.frag"
    source.write_bytes((REPO / "shaders_glsl" / "color.frag").read_bytes())
    (shipped / spirv_name("color.frag", source.read_bytes())).write_bytes(SHIPPED)
    monkeypatch.setattr(glsl, "packaged_folder", lambda kind: shipped if kind == "spirv" else None)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setenv("PATH", str(tmp_path / "no-bin"))
    assert glsl.compile_glsl(source) == SHIPPED
    source.write_bytes(source.read_bytes() + b"\n// edited\n")
    with pytest.raises(UserError, match="glslc not found.*not among the SPIR-V a wheel ships"):
        glsl.compile_glsl(source)


if __name__ == "__main__":
    lines = [f"{name} {' '.join(defines)}".strip() for name, defines in sorted(compiled_variants())]
    head = ("# Every GLSL variant the raw path compiles for the bundled course (stages and scenes, as `wgpurender\n"
            "# reference` draws them on this machine's plan): setup.py compiles each into the wheel. Regenerate with\n"
            "# python tests/test_spirv_shipped.py (tests/test_spirv_shipped.py checks it covers the course).\n")
    (REPO / "shaders_glsl" / VARIANTS_FILE).write_text(head + "\n".join(lines) + "\n")
    print(f"wrote {len(lines)} variants")
