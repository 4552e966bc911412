"""The README's tour, run as a new user runs it: every command in its first 42 lines, in order, from an empty folder.

``make demo`` is its recipe's render line (the Makefile's, with the venv's binary); a window (``demo``) gets
``--frames 2`` and a private Xvfb; the cache folders point into the test's folder (no machine-wide cache). A command
passes when it exits 0 and writes what it says it wrote; the report's line shares its run with tests/test_report.py
(conftest.py's ``report_run``, the same command), so the slow report is built once.
"""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from xvfb import xvfb_display  # noqa: F401  (the fixture ``display``)

from wgpurender.core.files.imageio import load_png

REPO = Path(__file__).resolve().parent.parent
TOUR_LINES = 42


def tour_commands() -> list[str]:
    """The shell commands of the README's first 42 lines (code blocks only, comments dropped)."""
    commands, inside = [], False
    for line in (REPO / "README.md").read_text().splitlines()[:TOUR_LINES]:
        if line.startswith("```"):
            inside = not inside
        elif inside and line.strip():
            commands.append(shlex.join(shlex.split(line, comments=True)))
    return commands


def make_demo_recipe() -> list[str]:
    """``make demo``'s command lines from the Makefile (``$(BIN)/`` is the venv's bin folder)."""
    lines = (REPO / "Makefile").read_text().splitlines()
    start = lines.index("demo: setup") + 1
    recipe = []
    for line in lines[start:]:
        if not line.startswith("\t"):
            break
        line = line.strip().lstrip("@")
        if line.startswith(("$(BIN)/wgpurender", "mkdir ")):
            recipe.append(line.replace("$(BIN)/", ""))
    return recipe


def argv(command: str) -> list[str]:
    words = shlex.split(command)
    if words[:2] == ["mkdir", "-p"]:
        return ["mkdir", "-p", *words[2:]]
    if words[0] == "wgpurender":
        words = [sys.executable, "-m", "wgpurender", *words[1:]]
        if words[3] == "demo":
            words += ["--frames", "2"]
    elif words[0] == "python":
        words[0] = sys.executable
    return words


def test_the_tour_is_the_ten_lines_after_the_set_up():
    commands = tour_commands()
    assert commands[:2] == ["make demo", "make test"]
    assert len(commands) == 12 and any("demo --raw final" in c for c in commands), commands


def test_every_tour_command_runs_from_an_empty_folder(tmp_path, display, report_run):
    if shutil.which("glslc") is None:
        pytest.skip("the raw path needs glslc (apt-get install glslc)")
    env = dict(os.environ, DISPLAY=display, XDG_CACHE_HOME=str(tmp_path / "cache"),
               WGPURENDER_PERF_RECORD=str(tmp_path / "bandwidth.json"))
    folder = tmp_path / "user"
    folder.mkdir()
    commands = tour_commands()
    ran = []
    for command in [*make_demo_recipe(), *commands[2:]]:  # make test is the suite this test is part of
        if command == report_run.command:
            result = report_run.result
        else:
            result = subprocess.run(argv(command), cwd=folder, env=env, capture_output=True, text=True, timeout=600)
        assert result.returncode == 0, f"{command}: exit {result.returncode}\n{result.stderr[-2000:]}"
        ran.append(command)
    assert any(c.startswith("wgpurender report") for c in ran), "the report's line is in the tour"
    assert load_png(folder / "out" / "final.png").shape[:2] == (600, 800)  # final.toml's [render] size
    for made in ("cubes.png", "ref.png", "d.png", "cubes.mp4"):
        assert (folder / made).stat().st_size > 0, made
    assert (report_run.folder / "out" / "report" / "index.html").is_file()


def test_the_raw_window_takes_a_bundled_scene_by_name(display, tmp_path):
    """Line 21's bug alone: `demo --raw final` resolved 'final' as a stage ("did you mean 'final'?")."""
    if shutil.which("glslc") is None:
        pytest.skip("the raw path needs glslc (apt-get install glslc)")
    result = subprocess.run([sys.executable, "-m", "wgpurender", "demo", "--raw", "final", "--frames", "1", "--size",
                             "64x48"], cwd=tmp_path, env=dict(os.environ, DISPLAY=display), capture_output=True,
                            text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "frames: 1" in result.stdout
