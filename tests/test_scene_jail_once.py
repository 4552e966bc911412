"""A scene's read rule (core/files/read_jail.py) is resolved once per scene, not once per file it names, and
still says the same: a bundled scene may read anything, another scene only its project folder, the bundled
assets and $WGPURENDER_ALLOW_PATHS. API-free."""

from __future__ import annotations

import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.files import assets, read_jail
from wgpurender.core.models import procedural
from wgpurender.core.scene.load import load_scene

SCENE = "[camera]\neye = [0.0, 0.0, 5.0]\ntarget = [0.0, 0.0, 0.0]\n\n"


def _scene(folder, models: list[str]):
    text = SCENE + "".join(f'[[models]]\npath = "{m}"\n\n' for m in models)
    path = folder / "s.toml"
    path.write_text(text)
    return path


def test_the_rule_is_asked_once_for_many_files(tmp_path, monkeypatch):
    names = [f"m{k}.obj" for k in range(5)]
    for name in names:
        procedural.write_obj(tmp_path / name, procedural.box(1.0))
    asked = []
    real = read_jail.scene_folders
    monkeypatch.setattr(read_jail, "scene_folders", lambda scene: asked.append(scene) or real(scene))
    scene = load_scene(_scene(tmp_path, names))
    assert len(scene.models) == 5 and len(asked) == 1


def test_a_bundled_scene_may_read_outside_and_another_may_not(tmp_path, monkeypatch):
    outside = tmp_path / "outside"
    outside.mkdir()
    procedural.write_obj(outside / "m.obj", procedural.box(1.0))
    layout = tmp_path / "layout"  # the bundled assets moved here, as a wheel's are elsewhere
    (layout / "assets" / "scenes").mkdir(parents=True)
    monkeypatch.setattr(assets, "CHECKOUT", layout)
    monkeypatch.setattr(assets, "PACKAGED", {**assets.PACKAGED, "assets": "_no_such_folder"})
    bundled = _scene(layout / "assets" / "scenes", ["../../../outside/m.obj"])
    assert len(load_scene(bundled).models) == 1
    mine = tmp_path / "mine" / "deep"
    mine.mkdir(parents=True)
    with pytest.raises(UserError, match="outside the folders a scene may read"):
        load_scene(_scene(mine, ["../../outside/m.obj"]))
