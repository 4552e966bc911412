"""An unknown render target names the bundled scenes too, and the closest name.

``wgpurender render finall -o x.png`` (a typo of the bundled scene ``final``, which README's first command
renders) said "unknown stage 'finall': valid stages are clear, ..., textured": no word that scenes are
targets too. The bundled scenes are the files in assets/scenes/ (read here, not from the code).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from wgpurender.cli import main

REPO = Path(__file__).resolve().parents[1]
BUNDLED = sorted(p.stem for p in (REPO / "assets" / "scenes").glob("*.toml"))


@pytest.mark.parametrize("command", ["render", "reference"])
def test_typo_of_a_scene_names_it(capsys, tmp_path, command):
    assert "final" in BUNDLED
    out = tmp_path / "x.png"
    assert main([command, "finall", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and not out.exists()
    assert "did you mean 'final'" in err[0]
    assert all(name in err[0] for name in BUNDLED)  # every bundled scene is offered
    assert "triangle" in err[0]  # and the stages still are


def test_typo_of_a_stage_names_it(capsys, tmp_path):
    assert main(["render", "triangel", "-o", str(tmp_path / "x.png")]) == 2
    assert "did you mean 'triangle'" in capsys.readouterr().err
