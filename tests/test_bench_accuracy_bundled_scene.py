"""bench accuracy finds its scene as every other command does: a path, or a bundled scene by name.

From any folder but the checkout's root (the wheel's users: README says the course works from any folder),
``wgpurender bench accuracy`` refused its own default ('scene file not found: assets/scenes/final.toml') and
``bench accuracy final`` refused the name that render, reference and export accept. The checks here stop at the
first refusal after the scene is found (--knob with --truth analytic), so nothing is timed.
"""

from __future__ import annotations

import pytest

from wgpurender.cli import main


def _run(capsys, argv: list[str]) -> tuple[int, str]:
    try:
        code = main(argv)
    except SystemExit as exit_:
        code = exit_.code
    return code, capsys.readouterr().err


@pytest.mark.parametrize("scene", [[], ["final"], ["final.toml"], ["assets/scenes/final.toml"]])
def test_scene_found_from_another_folder(capsys, tmp_path, monkeypatch, scene):
    monkeypatch.chdir(tmp_path)
    code, err = _run(capsys, ["bench", "accuracy", *scene, "--truth", "analytic", "--knob", "msaa"])
    assert code == 2 and "not found" not in err and "--knob" in err  # got past the scene to the next check
    assert list(tmp_path.iterdir()) == []  # a refused command writes nothing


def test_a_missing_scene_is_still_refused(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, err = _run(capsys, ["bench", "accuracy", "nosuch.toml", "--quick"])
    assert code == 2 and "scene file not found: nosuch.toml" in err and len(err.strip().splitlines()) == 1
