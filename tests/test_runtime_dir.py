"""With $XDG_RUNTIME_DIR unset or invalid, a command prints nothing on stderr but its own words (issue 28.13).

Before: every command that made a Vulkan instance (wgpu-native's or the raw path's) printed "error:
XDG_RUNTIME_DIR is invalid or not set in the environment." four times (libwayland, through Mesa's WSI) before its
output: SSH as root, containers, CI, notebooks. core/files/runtime_dir.py gives the process a private folder first.
"""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from wgpurender.core.files import runtime_dir

COMMANDS = [  # (argv after "wgpurender", exit code, stderr lines)
    (["render", "triangle", "-o", "{out}/a.png", "--size", "32x24"], 0, 0),
    (["reference", "triangle", "-o", "{out}/b.png", "--size", "32x24"], 0, 0),
    (["render", "no-such-stage", "-o", "{out}/c.png"], 2, 1),
    (["info"], 0, 0),
]


def _env(tmp_path, value: str | None) -> dict:
    env = {k: v for k, v in os.environ.items() if k != "XDG_RUNTIME_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path / "cache")
    if value is not None:
        env["XDG_RUNTIME_DIR"] = value
    return env


@pytest.mark.parametrize("value", [None, "relative/dir"], ids=["unset", "relative"])
@pytest.mark.parametrize("argv, code, lines", COMMANDS, ids=["-".join(c[0][:2]) for c in COMMANDS])
def test_stderr_holds_only_the_commands_own_lines(tmp_path, value, argv, code, lines):
    if value == "relative/dir":
        (tmp_path / "relative" / "dir").mkdir(parents=True)
    argv = [a.format(out=tmp_path) for a in argv]
    done = subprocess.run([sys.executable, "-m", "wgpurender", *argv], env=_env(tmp_path, value), cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == code, done.stderr
    assert "XDG_RUNTIME_DIR" not in done.stderr
    assert len(done.stderr.splitlines()) == lines, done.stderr


def test_a_valid_runtime_dir_is_kept(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    assert runtime_dir.ensure_runtime_dir() == str(tmp_path)
    assert os.environ["XDG_RUNTIME_DIR"] == str(tmp_path)


@pytest.mark.parametrize("value", [None, "", "run/user", "/no/such/folder"])
def test_an_invalid_one_is_replaced_by_a_private_folder(monkeypatch, tmp_path, value):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "run" / "user").mkdir(parents=True)  # a relative path that exists is still refused by libwayland
    if value is None:
        monkeypatch.delenv("XDG_RUNTIME_DIR", raising=False)
    else:
        monkeypatch.setenv("XDG_RUNTIME_DIR", value)
    made = runtime_dir.ensure_runtime_dir()
    assert os.environ["XDG_RUNTIME_DIR"] == made and os.path.isabs(made) and os.path.isdir(made)
    assert os.stat(made).st_mode & 0o777 == 0o700 and os.stat(made).st_uid == os.getuid()
    assert runtime_dir.ensure_runtime_dir() == made  # valid now: kept


SUCCESSES = [  # (argv after "wgpurender"): each succeeds and must print nothing on stderr (the newcomer's list)
    ["render", "3d", "-o", "{out}/d.png", "--size", "32x24"],
    ["reference", "3d", "-o", "{out}/e.png", "--size", "32x24"],
    ["compare", "{out}/grey.png", "{out}/grey.png"],
    ["export", "triangle", "-o", "{out}/page", "--size", "32x24"],
    ["exercise", "2a", "-o", "{out}/ex"],
    ["check", "2a", "{out}/solution.py", "--out", "{out}/checked", "--timeout", "120"],
    ["new", "{out}/proj"],
]


def _inputs(folder) -> None:
    """What compare and check read, made here: a grey PNG, the step 2a solution."""
    from PIL import Image

    from wgpurender.exercises import source
    from wgpurender.exercises.catalogue import exercise

    Image.new("RGBA", (8, 6), (128, 128, 128, 255)).save(folder / "grey.png")
    (folder / "solution.py").write_text(source.solution_source(exercise("2a", "wgpu")))


@pytest.mark.parametrize("argv", SUCCESSES, ids=[a[0] + "-" + a[1].split("/")[-1] for a in SUCCESSES])
def test_a_successful_command_prints_nothing_on_stderr_without_a_runtime_dir(tmp_path, argv):
    _inputs(tmp_path)
    argv = [a.format(out=tmp_path) for a in argv]
    done = subprocess.run([sys.executable, "-m", "wgpurender", *argv], env=_env(tmp_path, None), cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stderr == "", done.stderr
