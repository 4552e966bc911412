"""The report's line for a tutorial scene it cannot render names the folder the scene itself reads.

Installed from a wheel, the report said "looked for in .../lib/python3.11/shared/anchors/vulkan-tutorial" (the
checkout's layout), while the scene, bundled under site-packages/wgpurender/_assets/scenes, reads
site-packages/shared/anchors: the user was sent to a folder that would not have helped.
"""

from __future__ import annotations

import shutil
import tomllib
from pathlib import Path

from wgpurender.report.build import missing_line

SCENE = Path(__file__).resolve().parent.parent / "assets" / "scenes" / "vulkan_tutorial_28.toml"


def test_the_folder_named_is_where_the_scene_looks_in_a_wheel_layout(tmp_path):
    scenes = tmp_path / "site-packages" / "wgpurender" / "_assets" / "scenes"
    scenes.mkdir(parents=True)
    copy = scenes / SCENE.name
    shutil.copyfile(SCENE, copy)
    model = tomllib.loads(SCENE.read_text())["models"][0]["path"]  # "../../../shared/anchors/vulkan-tutorial/..."
    folder = (scenes / model).resolve().parent
    assert folder.is_relative_to(tmp_path / "site-packages")  # the wheel's layout, not this checkout's
    line = missing_line(copy, "not found")
    assert f"looked for in {folder})" in line, line
