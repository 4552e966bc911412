"""A bundled tutorial scene read away from ../shared/anchors refuses with one line that says why.

``vulkan_tutorial_28.toml`` and ``_30`` draw the C++ tutorial's own model and texture, read from the anchors
folder beside the repository (never copied into it, never in the wheel). ``wgpurender info`` lists them among
the bundled scenes, so a user of the wheel or of a lone clone tries them: the refusal must name that folder
and say it is not shipped, instead of only "not found" under a path that cannot exist (site-packages/shared).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.scene import load_scene

REPO = Path(__file__).resolve().parents[1]
SCENES = ["vulkan_tutorial_28.toml", "vulkan_tutorial_30.toml"]


def _lone_copy(tmp_path: Path, name: str) -> Path:
    """The scene three folders deep in tmp_path, so its ../../../shared/anchors paths point at nothing."""
    folder = tmp_path / "a" / "b" / "c"
    folder.mkdir(parents=True)
    copy = folder / name
    shutil.copy(REPO / "assets" / "scenes" / name, copy)
    assert "shared/anchors" in copy.read_text()
    assert not (tmp_path / "shared").exists()
    return copy


@pytest.mark.parametrize("name", SCENES)
def test_loading_names_the_anchors_folder(tmp_path: Path, name: str) -> None:
    with pytest.raises(UserError) as err:
        load_scene(_lone_copy(tmp_path, name))
    message = str(err.value)
    assert "\n" not in message
    assert "not found" in message
    assert "../shared/anchors" in message.split("not found", 1)[1].split(")", 1)[1]  # the hint, after the paths
    assert "not ship" in message


def test_cli_refuses_in_one_line(tmp_path: Path) -> None:
    scene = _lone_copy(tmp_path, SCENES[0])
    out = tmp_path / "v.png"
    run = subprocess.run([sys.executable, "-m", "wgpurender", "render", str(scene), "-o", str(out)],
                         capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert run.returncode == 2
    lines = [ln for ln in run.stderr.splitlines() if ln.startswith("wgpurender")]
    assert len(lines) == 1 and "../shared/anchors" in lines[0] and "not ship" in lines[0]
    assert "Traceback" not in run.stderr
    assert not out.exists()
