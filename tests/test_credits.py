"""The tutorial's CC BY model and texture carry their attribution wherever they are published: the report's
sections of the tutorial scenes, exported pages of them, the wheel's data (tests/test_wheel.py), README."""

from __future__ import annotations

import html
import shutil
from pathlib import Path

import pytest

from wgpurender.core.files.assets import scene_dir
from wgpurender.core.files.credits import all_credits
from wgpurender.core.scene.credits import scene_credits

REPO = Path(__file__).resolve().parent.parent
LICENCE = "CC BY 4.0"  # the licence of the Vulkan tutorial's viking room (en/08_Loading_models.md)


def test_the_table_credits_the_viking_room_with_title_author_source_and_licence():
    [credit] = [c for c in all_credits() if "viking_room.obj" in c.files]
    assert set(credit.files) == {"viking_room.obj", "viking_room.png"}
    line = credit.line()
    for part in ("Viking room", "nigelgoh", "sketchfab.com", LICENCE, "creativecommons.org/licenses/by/4.0"):
        assert part in line, part


def test_a_scene_is_credited_exactly_when_it_reads_the_model_or_texture():
    for path in sorted(scene_dir().glob("*.toml")):
        text = path.read_text()
        reads = "viking_room." in text
        assert bool(scene_credits(path)) == reads, path.name


def test_the_readme_carries_the_attribution():
    text = " ".join((REPO / "README.md").read_text().split())
    for credit in all_credits():
        assert " ".join(credit.line().split()) in text


def test_the_report_credits_the_tutorial_scenes_even_where_their_files_are_absent(tmp_path, monkeypatch, ctx):
    from wgpurender.report import build

    scenes = tmp_path / "scenes"
    scenes.mkdir()
    shutil.copy(scene_dir() / "vulkan_tutorial_28.toml", scenes)  # its relative paths now lead nowhere
    monkeypatch.setattr(build, "SCENE_DIR", scenes)
    monkeypatch.setattr(build, "SCENES", ("vulkan_tutorial_28",))
    index = build.build_report(tmp_path / "site", size=(64, 48), stages=[], ctx=ctx, accuracy=False,
                               log=lambda _text: None)
    text = index.read_text()
    part = text[text.index('id="vulkan_tutorial_28"'):]
    assert html.escape(all_credits()[0].line()) in part


def test_an_exported_page_of_a_tutorial_scene_carries_the_attribution(tmp_path):
    from wgpurender.webpage import page_html

    anchors = REPO.parent / "shared" / "anchors" / "vulkan-tutorial"
    meta = {"name": "vulkan_tutorial_28", "summary": "s", "size": [8, 8], "controls": "", "exported": "", "plan": "",
            "credits": [c.line() for c in scene_credits(scene_dir() / "vulkan_tutorial_28.toml")]}
    assert html.escape(meta["credits"][0]) in page_html(meta)
    from wgpurender.webpage import export

    final = export("final", tmp_path / "final", (32, 24)).page
    assert "Credit:" not in final.read_text()  # only what shows the credited files
    if not anchors.is_dir():
        pytest.skip(f"the tutorial's files are absent ({anchors}): the page itself cannot be exported here")
    page = export(str(scene_dir() / "vulkan_tutorial_28.toml"), tmp_path / "page", (80, 60)).page
    assert html.escape(all_credits()[0].line()) in page.read_text()
