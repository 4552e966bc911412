"""Issue 28, item 2: an exported page carries no absolute path of the machine that made it. The scene names its
model and texture by absolute paths (the repository's assets) from a folder with a space in its name; no file
of the page may contain the repository's, the scene's, the temp or the home folder."""

from __future__ import annotations

from pathlib import Path

import pytest

from wgpurender.core.files.published_text import labels_without_machine_paths, without_machine_paths

REPO = Path(__file__).resolve().parents[1]
ASSETS = REPO / "assets"


def test_an_exported_scene_page_names_files_but_no_folders_of_this_machine(tmp_path):
    from wgpurender.webpage import export

    folder = tmp_path / "my project"
    folder.mkdir()
    scene = folder / "scene.toml"
    scene.write_text(
        "[camera]\neye = [0, 1.5, 4]\ntarget = [0, 0, 0]\n\n[render]\nmsaa = 1\n\n"
        f'[[models]]\npath = "{ASSETS / "models" / "gltf_features.glb"}"\n\n'
        f'[[models]]\npath = "{ASSETS / "models" / "brick_cube.obj"}"\n'
        f'material = {{ albedo_map = "{ASSETS / "textures" / "brick_albedo.png"}" }}\n')
    done = export(str(scene), tmp_path / "page", (48, 36))
    texts = {p.name: p.read_text(errors="replace") for p in done.page.parent.iterdir() if p.is_file()}
    assert {"index.html", "data.js"} <= set(texts)
    machine = {str(REPO), str(ASSETS), str(folder), str(tmp_path), "/tmp/", "/work/", "/root/"}
    if str(Path.home()) != "/":
        machine.add(str(Path.home()))
    for name, text in texts.items():
        found = sorted(m for m in machine if m in text)
        assert not found, f"{name} carries {found}"
    assert "gltf_features.glb" in texts["data.js"] and "brick_albedo.png" in texts["data.js"]  # names stay


@pytest.mark.parametrize(("text", "public"), [
    ("scene: /home/alice/work/scene.toml", "scene: scene.toml"),
    ("models[0] '/a/b c/m.glb' material", "models[0] 'm.glb' material"),  # the known folder "/a/b c" goes whole
    ("C:\\Users\\al\\m.glb and ~/x/y.png", "m.glb and y.png"),
    ("filter linear/linear, x / y, 1/2, a.b/c, models/rel.png", "filter linear/linear, x / y, 1/2, a.b/c, "
                                                                "models/rel.png"),
])
def test_machine_folders_are_removed_and_relative_text_stays(text, public):
    assert without_machine_paths(text, ["/a/b c"]) == public


def test_only_labels_of_recorded_calls_are_rewritten():
    """Shader code and base64 blobs hold slashes that are not paths: only ``label`` values change."""
    calls = [{"m": "createShaderModule", "d": {"code": "let a = b / c; // /x/y/z", "label": "/srv/m/x.glb"}},
             {"m": "createBuffer", "d": [{"label": "models[0] '/srv/m/a.glb'"}, "/keep/this"]}]
    assert labels_without_machine_paths(calls) == [
        {"m": "createShaderModule", "d": {"code": "let a = b / c; // /x/y/z", "label": "x.glb"}},
        {"m": "createBuffer", "d": [{"label": "models[0] 'a.glb'"}, "/keep/this"]}]
