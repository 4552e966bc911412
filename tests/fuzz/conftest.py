"""Fuzz tests: bounded in ``make test``; ``make fuzz`` (WGPURENDER_FUZZ=long) raises the example counts and prints,
and writes to $WGPURENDER_FUZZ_REPORT, the counts by outcome."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import harness  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(scope="session", autouse=True)
def warm_up(tmp_path_factory):
    """One render outside any case's time bound: the first pays for the GPU device, the imports and shader
    compilation, which on a loaded machine took longer than the per-case bound (and read as a hang)."""
    from reliab_gen import run_cli, scene_text, triangle_gltf, write_gltf

    folder = tmp_path_factory.mktemp("warm")
    write_gltf(folder / "model.gltf", triangle_gltf())
    (folder / "scene.toml").write_text(scene_text())
    code, _, err = run_cli(*harness.render_argv(folder / "scene.toml", folder / "out.png"))
    assert code == 0, err


def pytest_terminal_summary(terminalreporter):
    if not harness.OUTCOMES:
        return
    terminalreporter.write_line(harness.summary())
    for outcome, examples in sorted(harness.EXAMPLES.items()):
        terminalreporter.write_line(f"  {outcome}: {len(examples)}, first: {examples[0][:600]}")
    report = os.environ.get("WGPURENDER_FUZZ_REPORT")
    if report:
        Path(report).write_text(json.dumps({"counts": dict(harness.OUTCOMES),
                                            "examples": {k: v[:5] for k, v in harness.EXAMPLES.items()}}, indent=1))


def pytest_sessionfinish(session, exitstatus):
    """``make fuzz`` counts every case instead of stopping at the first bad one: it fails here if any was bad."""
    if harness.LONG and any(k not in harness.PASSING for k in harness.OUTCOMES):
        session.exitstatus = 1
