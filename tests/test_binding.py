"""The Dawn binding (issue 31.8): chosen by $WGPURENDER_BINDING, refused with one line where Dawn has no adapter.

Run in child processes: the binding is chosen once per process, before wgpu is imported."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from wgpurender.wgpu_path import binding


def _render(env_value: str, tmp_path) -> subprocess.CompletedProcess:
    env = {**os.environ, "WGPURENDER_BINDING": env_value, "XDG_RUNTIME_DIR": os.environ.get("XDG_RUNTIME_DIR", "/tmp")}
    return subprocess.run([sys.executable, "-m", "wgpurender", "render", "triangle", "-o", str(tmp_path / "t.png"),
                           "--size", "32x24"], capture_output=True, text=True, env=env, timeout=120)


def test_an_unknown_binding_is_one_line(tmp_path):
    done = _render("metal-please", tmp_path)
    assert done.returncode == 2
    assert done.stderr.strip().count("\n") == 0 and "wgpu-native or dawn" in done.stderr
    assert not (tmp_path / "t.png").exists()


def test_dawn_renders_or_refuses_in_one_line(tmp_path, ctx):
    pytest.importorskip("wgpudawn")
    done = _render("dawn", tmp_path)
    if ctx.adapter.info["adapter_type"] == "CPU":  # lavapipe: Dawn finds no adapter
        assert done.returncode == 2, done.stderr
        assert done.stderr.strip().count("\n") == 0, done.stderr
        assert "Dawn (wgpudawn) offers no adapter" in done.stderr and "WGPURENDER_BINDING" in done.stderr
        assert not (tmp_path / "t.png").exists()
    else:
        assert done.returncode == 0, done.stderr
        assert (tmp_path / "t.png").stat().st_size > 0


def test_the_default_is_wgpu_native(monkeypatch):
    monkeypatch.delenv(binding.BINDING_ENV, raising=False)
    assert binding.requested() == "wgpu-native"
