"""Shader and pipeline errors are one line naming the shader file and the problem (exit 2), and the SPIR-V cache
falls back to memory when its folder cannot be written. Each case runs the CLI in a subprocess: a pipeline
error is a GPU validation error, which the suite's fixture would (rightly) count as a bug in-process."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def _cli(*argv, **env):
    run_env = {**os.environ, "XDG_RUNTIME_DIR": os.environ.get("XDG_RUNTIME_DIR", "/tmp"), **env}
    return subprocess.run([sys.executable, "-m", "wgpurender", *map(str, argv)], env=run_env, capture_output=True,
                          text=True, timeout=300)


def _our_lines(stderr: str) -> list[str]:
    """Our stderr lines (the drivers may print their own, e.g. Mesa about its cache, before Python runs)."""
    return [line for line in stderr.splitlines() if line.startswith("wgpurender") or "Traceback" in line]


def _shaders(tmp_path, name, old, new):
    folder = tmp_path / "wgsl"
    shutil.copytree(REPO / "shaders_wgsl", folder)
    text = (folder / name).read_text()
    assert old in text
    (folder / name).write_text(text.replace(old, new))
    return folder


@pytest.mark.parametrize("stage, name, old, new, needle", [
    ("triangle", "triangle.wgsl", "fn vs_main", "fn vs_renamed", "Unable to find entry point 'vs_main'"),
    ("3d", "cube3d.wgsl", "@group(0) @binding(0) var<uniform> camera", "@group(0) @binding(3) var<uniform> camera",
     "ResourceBinding { group: 0, binding: 3 } is not available in the pipeline layout"),
])
def test_wgsl_that_does_not_fit_its_pipeline(tmp_path, stage, name, old, new, needle):
    folder = _shaders(tmp_path, name, old, new)
    result = _cli("render", stage, "-o", tmp_path / "x.png", "--size", "16x16", WGPURENDER_SHADERS=str(folder))
    lines = _our_lines(result.stderr)
    assert result.returncode == 2 and len(lines) == 1, result.stderr
    assert f"shader {name.removesuffix('.wgsl')}" in lines[0] and needle in lines[0] and str(folder) in lines[0]
    assert not (tmp_path / "x.png").exists()


def test_glsl_compile_error_names_the_file(tmp_path):
    folder = tmp_path / "glsl"
    shutil.copytree(REPO / "shaders_glsl", folder)
    (folder / "triangle.vert").write_text("#version 450\nvoid main() { oops; }\n")
    result = _cli("reference", "triangle", "-o", tmp_path / "x.png", "--size", "16x16", WGPURENDER_GLSL=str(folder),
                  XDG_CACHE_HOME=str(tmp_path / "cache"))
    lines = _our_lines(result.stderr)
    assert result.returncode == 2 and len(lines) == 1, result.stderr
    assert f"{folder / 'triangle.vert'} line 2" in lines[0] and "oops" in lines[0]


def test_spirv_cache_falls_back_to_memory_when_not_writable(tmp_path):
    not_a_folder = tmp_path / "cache-is-a-file"
    not_a_folder.write_text("")  # root may write anywhere, but nobody can make a folder inside a file
    result = _cli("reference", "triangle", "-o", tmp_path / "x.png", "--size", "16x16",
                  XDG_CACHE_HOME=str(not_a_folder))
    assert result.returncode == 0, result.stderr
    assert _our_lines(result.stderr) == [] and (tmp_path / "x.png").is_file()
