"""Stages keep no id()-keyed caches and create their state in __init__/setup (issue 32 item 2: stages 4 and 5).

An id() key can match a new object that reuses a freed one's address (the camera cache once had to keep the old
camera alive for that); an attribute born on first use (getattr/hasattr with a default) hides from a reader what
a stage holds."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

STAGES = sorted((Path(__file__).resolve().parent.parent / "wgpurender").glob("*_path/stages/*.py"))


@pytest.mark.parametrize("path", STAGES, ids=[f"{p.parent.parent.name}/{p.name}" for p in STAGES])
def test_no_id_keys_and_no_late_attributes(path):
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            if node.func.id == "id":
                found.append(f"line {node.lineno}: id()")
            if node.func.id in ("getattr", "hasattr") and node.args and getattr(node.args[0], "id", "") == "self":
                found.append(f"line {node.lineno}: {node.func.id}(self, ...)")
    assert found == []


def test_the_camera_block_is_written_when_its_values_change(ctx):
    """Stage 3d writes its camera uniform block when the camera's values or the aspect change, not otherwise."""
    import dataclasses

    from wgpurender.wgpu_path.stages.cube3d import Cube3D

    stage = Cube3D(ctx, "rgba8unorm")
    stage.resize((64, 48))
    writes = []
    real = ctx.queue.write_buffer

    class Queue:
        def write_buffer(self, buffer, offset, data):
            if buffer is stage.camera_buffer:
                writes.append(bytes(data))
            real(buffer, offset, data)

    stage.ctx = type("Ctx", (), {"queue": Queue()})()
    stage.update_uniforms(0.0)
    stage.update_uniforms(0.5)  # the same camera: not rewritten
    stage.camera = dataclasses.replace(stage.camera)  # a new object with the same values: not rewritten
    stage.update_uniforms(1.0)
    assert len(writes) == 1
    stage.camera = dataclasses.replace(stage.camera, fov_y=stage.camera.fov_y + 10)
    stage.update_uniforms(1.0)
    stage.resize((64, 64))
    stage.update_uniforms(1.0)
    assert len(writes) == 3 and len(set(writes)) == 3
