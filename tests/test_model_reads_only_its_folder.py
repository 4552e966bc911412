"""Issue 28, item 1: a model reads only what it ships (read_jail.py). Each case is built here at run time: a
secret file outside the model's folder, links, FIFOs, devices; a glTF or OBJ that names it. The render must end
in one line naming the URI, with exit 2, and no file outside the model's folder may have been opened: a Python
audit hook (``open`` events, independent of the loader) records every file the process opens during the call."""

from __future__ import annotations

import base64
import os
import sys
from pathlib import Path

import pytest
from helpers import one_line_refusal
from reliab_gen import run_cli, scene_text, triangle_gltf, write_gltf

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail

OPENED: list[str] | None = None


def _audit(event: str, args: tuple) -> None:
    if event == "open" and OPENED is not None and isinstance(args[0], (str, bytes, os.PathLike)):
        OPENED.append(os.fsdecode(args[0]))


sys.addaudithook(_audit)


def _render_opening(scene: Path, out: Path) -> tuple[int, str, list[str]]:
    """Render ``scene``; (exit code, stderr, every file path opened meanwhile)."""
    global OPENED
    OPENED = []
    try:
        code, _, err = run_cli("render", scene, "-o", out, "--size", "32x24")
        return code, err, OPENED
    finally:
        OPENED = None



def _external_buffer_doc(uri: str) -> dict:
    """triangle_gltf with its buffer moved out of the data: URI into the file ``uri`` names."""
    doc = triangle_gltf()
    doc["buffers"][0]["uri"] = uri
    return doc


def _buffer_bytes() -> bytes:
    return base64.b64decode(triangle_gltf()["buffers"][0]["uri"].split(",", 1)[1])


@pytest.fixture
def world(tmp_path):
    """tmp/model/ (the model's folder, with the scene) and tmp/outside/secret.bin (a valid buffer: read today)."""
    (tmp_path / "model").mkdir()
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "secret.bin").write_bytes(_buffer_bytes())
    (tmp_path / "model" / "scene.toml").write_text(scene_text("model.gltf"))
    return tmp_path


def _outside_opened(opened: list[str], world: Path) -> list[str]:
    named = ("/proc/self/environ", "/dev/zero")
    return [p for p in opened if str(world / "outside") in os.path.abspath(p) or p in named]


URIS = {  # name -> uri, given the world folder
    "absolute": lambda w: str(w / "outside" / "secret.bin"),
    "file-url": lambda w: (w / "outside" / "secret.bin").as_uri(),
    "dotdot": lambda w: "../outside/secret.bin",
    "percent-dotdot": lambda w: "%2e%2e/outside/secret.bin",
    "percent-slash": lambda w: "..%2Foutside%2Fsecret.bin",
    "proc-environ": lambda w: "/proc/self/environ",
    "device": lambda w: "/dev/zero",
    "link-out": lambda w: "inside.bin",  # a link in the folder pointing at ../outside/secret.bin
    "link-dir-out": lambda w: "sub/secret.bin",  # a folder link in the model's folder pointing outside
}


@pytest.mark.parametrize("kind", sorted(URIS))
def test_a_buffer_uri_outside_the_models_folder_is_refused_before_reading(world, kind):
    uri = URIS[kind](world)
    (world / "model" / "inside.bin").symlink_to(world / "outside" / "secret.bin")
    (world / "model" / "sub").symlink_to(world / "outside")
    write_gltf(world / "model" / "model.gltf", _external_buffer_doc(uri))
    code, err, opened = _render_opening(world / "model" / "scene.toml", world / "out.png")
    one_line_refusal(code, err, repr(uri), "$.buffers[0].uri", "its own folder")
    assert not _outside_opened(opened, world), opened
    assert not (world / "out.png").exists()


@pytest.mark.parametrize("kind", ["fifo", "device-link", "directory"])
def test_a_special_file_inside_the_folder_is_refused_without_opening_it(world, kind):
    special = world / "model" / "special.bin"
    if kind == "fifo":
        os.mkfifo(special)  # opening it for reading would block the render for good
    elif kind == "device-link":
        special.symlink_to("/dev/zero")
    else:
        special.mkdir()
    write_gltf(world / "model" / "model.gltf", _external_buffer_doc("special.bin"))
    code, err, opened = _render_opening(world / "model" / "scene.toml", world / "out.png")
    one_line_refusal(code, err, "'special.bin'")
    assert str(special) not in opened and "/dev/zero" not in opened


@pytest.mark.parametrize("bad", ["$.buffers[1].uri", "$.images[0].uri"])
def test_every_uri_is_checked_before_the_first_buffer_is_read(world, bad):
    """Buffer 0 is legal, buffer 1 or image 0 is outside: the refusal comes before buffer 0's file is opened."""
    (world / "model" / "good.bin").write_bytes(_buffer_bytes())
    doc = _external_buffer_doc("good.bin")
    if bad.startswith("$.buffers"):
        doc["buffers"].append({"uri": "../outside/secret.bin", "byteLength": 4})
    else:
        doc["images"] = [{"uri": "../outside/secret.png"}]
    write_gltf(world / "model" / "model.gltf", doc)
    code, err, opened = _render_opening(world / "model" / "scene.toml", world / "out.png")
    one_line_refusal(code, err, bad)
    assert str(world / "model" / "good.bin") not in opened


@pytest.mark.parametrize("kind", ["absolute", "dotdot", "percent-dotdot", "link-out"])
def test_an_image_uri_outside_the_models_folder_is_refused(world, kind):
    from PIL import Image

    Image.new("RGBA", (2, 2), (255, 0, 0, 255)).save(world / "outside" / "secret.png")
    (world / "model" / "inside.png").symlink_to(world / "outside" / "secret.png")
    uri = {"absolute": str(world / "outside" / "secret.png"), "dotdot": "../outside/secret.png",
           "percent-dotdot": "%2E%2E/outside/secret.png", "link-out": "inside.png"}[kind]
    doc = triangle_gltf()
    doc.update(images=[{"uri": uri}], textures=[{"source": 0}],
               materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}])
    doc["meshes"][0]["primitives"][0]["material"] = 0
    write_gltf(world / "model" / "model.gltf", doc)
    (world / "model" / "scene.toml").write_text(scene_text(None) + '\n[[models]]\npath = "model.gltf"\n')
    code, err, opened = _render_opening(world / "model" / "scene.toml", world / "out.png")
    one_line_refusal(code, err, repr(uri), "$.images[0].uri")
    assert not [p for p in opened if "secret.png" in p], opened


def test_files_inside_the_folder_and_data_uris_still_load(world):
    """The rule keeps what a model ships: a buffer in a subfolder, named through ``sub/../``, loads and renders."""
    (world / "model" / "bin").mkdir()
    (world / "model" / "bin" / "data.bin").write_bytes(_buffer_bytes())
    write_gltf(world / "model" / "model.gltf", _external_buffer_doc("bin/../bin/data.bin"))
    code, _, err = run_cli("render", world / "model" / "scene.toml", "-o", world / "out.png", "--size", "32x24")
    assert code == 0, err
    from wgpurender.core.models.gltf_io import read_document

    assert read_document(world / "model" / "model.gltf").buffers[0] == _buffer_bytes()


# --- OBJ: mtllib and the MTL's textures ----------------------------------------------------------------------

OBJ = "mtllib {lib}\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0.5 1\nusemtl m\nf 1/1 2/2 3/3\n"


@pytest.mark.parametrize("where", ["mtllib", "map_Kd"])
@pytest.mark.parametrize("how", ["dotdot", "absolute", "link-out"])
def test_an_obj_reads_neither_a_material_library_nor_a_texture_outside_its_folder(world, where, how):
    from PIL import Image

    Image.new("RGBA", (2, 2), (0, 255, 0, 255)).save(world / "outside" / "secret.png")
    (world / "outside" / "evil.mtl").write_text("newmtl m\nmap_Kd secret.png\n")
    (world / "model" / "evil.mtl").symlink_to(world / "outside" / "evil.mtl")
    (world / "model" / "secret.png").symlink_to(world / "outside" / "secret.png")
    name = {"dotdot": "../outside/{}", "absolute": str(world / "outside") + "/{}", "link-out": "{}"}[how]
    if where == "mtllib":
        lib = name.format("evil.mtl")
    else:
        lib = "ok.mtl"
        (world / "model" / "ok.mtl").write_text(f"newmtl m\nKd 1 1 1\nmap_Kd {name.format('secret.png')}\n")
    (world / "model" / "model.obj").write_text(OBJ.format(lib=lib))
    (world / "model" / "scene.toml").write_text(scene_text(None) + '\n[[models]]\npath = "model.obj"\n')
    code, err, opened = _render_opening(world / "model" / "scene.toml", world / "out.png")
    one_line_refusal(code, err, "mtllib" if where == "mtllib" else "map_Kd", "its own folder")
    assert not [p for p in opened if "outside" in p], opened


def test_trimeshs_resolver_is_jailed_too(world):
    """OBJ and PLY go through trimesh with skip_materials; should trimesh ask for a file anyway, the resolver the
    loader hands it refuses one outside the model's folder."""
    from wgpurender.core.models.mesh import _jailed_resolver

    (world / "model" / "model.obj").write_text(OBJ.format(lib="x.mtl"))
    (world / "model" / "x.mtl").write_text("newmtl m\n")
    resolver = _jailed_resolver(world / "model" / "model.obj")
    assert resolver.get("x.mtl") == b"newmtl m\n"
    with pytest.raises(UserError, match="its own folder"):
        resolver.get("../outside/secret.bin")


# --- the rule itself -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("uri", ["C:/x.bin", "C:\\x.bin", "\\\\server\\share\\x.bin", "http://example.com/x.bin",
                                 "file:x.bin", "/x.bin"])
def test_absolute_and_schemed_uris_are_refused(tmp_path, uri):
    with pytest.raises(UserError, match="absolute or has a scheme"):
        read_jail.model_file(tmp_path / "m.gltf", uri, "$.buffers[0].uri")


@pytest.mark.parametrize("uri", ["a.bin", "sub/a.bin", "sub/../a.bin", "a%20b.bin", "./a.bin"])
def test_relative_names_inside_are_kept(tmp_path, uri):
    from urllib.parse import unquote

    assert read_jail.model_file(tmp_path / "m.gltf", uri, "$") == (tmp_path / unquote(uri)).resolve()


def test_a_bundled_model_reads_the_bundled_assets(tmp_path):
    """brick_cube.mtl (a model the project ships) names ../textures/: assets/ is its folder."""
    from wgpurender.core.files.assets import assets_dir

    model = assets_dir() / "models" / "brick_cube.obj"
    found = read_jail.model_file(model, "../textures/brick_albedo.png", "map_Kd", encoded=False)
    assert found == (assets_dir() / "textures" / "brick_albedo.png").resolve()
    with pytest.raises(UserError):
        read_jail.model_file(model, "../../setup.py", "map_Kd", encoded=False)


# --- a scene's own paths -------------------------------------------------------------------------------------

def _scene_naming(scene: Path, model: Path) -> Path:
    scene.parent.mkdir(parents=True, exist_ok=True)
    scene.write_text(scene_text(str(model)))
    return scene


def test_a_scene_reads_only_its_project_the_assets_and_allowed_folders(tmp_path, monkeypatch):
    monkeypatch.delenv(read_jail.ALLOW_ENV, raising=False)
    other = tmp_path / "elsewhere"
    other.mkdir()
    model = write_gltf(other / "model.gltf", triangle_gltf())
    scene = _scene_naming(tmp_path / "project" / "scene.toml", model)
    code, _, err = run_cli("render", scene, "-o", tmp_path / "a.png", "--size", "32x24")
    one_line_refusal(code, err, "scene.toml:", "models[0].path", read_jail.ALLOW_ENV)
    monkeypatch.setenv(read_jail.ALLOW_ENV, f"/nonexistent{os.pathsep}{other}")
    code, _, err = run_cli("render", scene, "-o", tmp_path / "b.png", "--size", "32x24")
    assert code == 0, err


def test_a_scene_in_a_scenes_folder_reads_its_project(tmp_path, monkeypatch):
    """project/scenes/s.toml may name ../models/m.gltf (the bundled layout), not ../../m.gltf."""
    monkeypatch.delenv(read_jail.ALLOW_ENV, raising=False)
    (tmp_path / "project" / "models").mkdir(parents=True)
    write_gltf(tmp_path / "project" / "models" / "m.gltf", triangle_gltf())
    write_gltf(tmp_path / "m.gltf", triangle_gltf())
    scene = _scene_naming(tmp_path / "project" / "scenes" / "s.toml", Path("../models/m.gltf"))
    code, _, err = run_cli("render", scene, "-o", tmp_path / "a.png", "--size", "32x24")
    assert code == 0, err
    _scene_naming(scene, Path("../../m.gltf"))
    code, _, err = run_cli("render", scene, "-o", tmp_path / "b.png", "--size", "32x24")
    one_line_refusal(code, err, "'../../m.gltf'", "outside the folders a scene may read")


def test_a_scene_link_pointing_out_is_refused_and_the_bundled_assets_are_allowed(tmp_path, monkeypatch):
    from wgpurender.core.files.assets import assets_dir

    monkeypatch.delenv(read_jail.ALLOW_ENV, raising=False)
    (tmp_path / "outside").mkdir()
    write_gltf(tmp_path / "outside" / "m.gltf", triangle_gltf())
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "m.gltf").symlink_to(tmp_path / "outside" / "m.gltf")
    scene = _scene_naming(tmp_path / "s" / "scene.toml", Path("m.gltf"))
    code, _, err = run_cli("render", scene, "-o", tmp_path / "a.png", "--size", "32x24")
    one_line_refusal(code, err, "outside the folders a scene may read")
    _scene_naming(scene, assets_dir() / "models" / "brick_torus.glb")
    code, _, err = run_cli("render", scene, "-o", tmp_path / "b.png", "--size", "32x24")
    assert code == 0, err



def test_a_blender_layout_is_refused_saying_how_and_loads_once_its_folder_is_allowed(tmp_path, monkeypatch):
    """models/x.obj + textures/y.png (the MTL names ../textures/y.png): the refusal says to move the texture or
    allow its folder, and $WGPURENDER_ALLOW_PATHS (the scenes' allow-list) lets the model read it."""
    from PIL import Image

    monkeypatch.delenv(read_jail.ALLOW_ENV, raising=False)
    (tmp_path / "models").mkdir()
    (tmp_path / "textures").mkdir()
    Image.new("RGBA", (2, 2), (0, 255, 0, 255)).save(tmp_path / "textures" / "y.png")
    (tmp_path / "models" / "x.mtl").write_text("newmtl m\nKd 1 1 1\nmap_Kd ../textures/y.png\n")
    (tmp_path / "models" / "x.obj").write_text(OBJ.format(lib="x.mtl"))
    scene = tmp_path / "scene.toml"
    scene.write_text(scene_text(None) + '\n[[models]]\npath = "models/x.obj"\n')
    code, _, err = run_cli("render", scene, "-o", tmp_path / "a.png", "--size", "32x24")
    textures = (tmp_path / "textures").resolve()
    line = one_line_refusal(code, err, "map_Kd", f"move the file under {(tmp_path / 'models').resolve()}")
    assert line.endswith(f"allow its folder with ${read_jail.ALLOW_ENV}={textures}"), line  # the folder, not y.png
    monkeypatch.setenv(read_jail.ALLOW_ENV, str(textures))
    code, _, err = run_cli("render", scene, "-o", tmp_path / "b.png", "--size", "32x24")
    assert code == 0, err
    assert (tmp_path / "b.png").is_file()
