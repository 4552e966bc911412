"""`wgpurender info` lists a bundled scene as renderable only when the files it names are there (the tutorial
scenes read ../shared/anchors, which a wheel never has): built here on a scene folder made in tmp_path."""

from __future__ import annotations

from wgpurender.cli import info
from wgpurender.core.files import assets


def test_a_scene_whose_model_is_absent_is_marked(tmp_path, monkeypatch):
    scenes = tmp_path / "repo" / "scenes"
    scenes.mkdir(parents=True)
    (tmp_path / "repo" / "here.obj").write_text("v 0 0 0\n")
    (scenes / "present.toml").write_text('[[models]]\npath = "../here.obj"\n')
    (scenes / "tutorial.toml").write_text('[[models]]\npath = "../here.obj"\n'
                                          'material = { albedo_map = "../../anchors/room.png" }\n')
    monkeypatch.setattr(assets, "scene_dir", lambda: scenes)
    assert info.scene_labels() == ["present", "tutorial" + info.NEEDS_FILES]
    (tmp_path / "anchors").mkdir()
    (tmp_path / "anchors" / "room.png").write_bytes(b"")  # the tutorial's files arrive
    assert info.scene_labels() == ["present", "tutorial"]
