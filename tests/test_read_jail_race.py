"""The read jail checks the file actually read (core/files/read_jail.open_checked), not only the path it checked:
a review finding was the check-then-open race, where a file or folder the check let through is swapped for a link
out of the model's folder (or a FIFO) before the reader opens it. Each case here makes the swap at run time,
between the check and the read, and the read must be refused in one line that names what the path became; no
byte of the file outside may come back (before the fix, the readers followed the link and returned it)."""

from __future__ import annotations

import base64
import json
import os
import threading
from pathlib import Path

import numpy as np
import pytest
from reliab_gen import triangle_gltf, write_gltf

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail

SECRET = b"the secret outside the model's folder"


@pytest.fixture
def world(tmp_path):
    """tmp/model/ (the model's folder: sub/data.bin inside it) and tmp/outside/ (sub/data.bin, the secret)."""
    for top, data in (("model", b"the model's own bytes"), ("outside", SECRET)):
        (tmp_path / top / "sub").mkdir(parents=True)
        (tmp_path / top / "sub" / "data.bin").write_bytes(data)
    return tmp_path


def _refused(call, *needles: str) -> str:
    with pytest.raises(UserError) as err:
        call()
    message = str(err.value)
    assert "\n" not in message and "changed between its check and its read" in message, message
    assert all(n in message for n in needles), message
    return message


def _checked(world: Path) -> Path:
    return read_jail.model_file(world / "model" / "m.gltf", "sub/data.bin", "$.buffers[0].uri")


def test_an_unchanged_file_reads_as_checked(world):
    assert read_jail.read_checked(_checked(world)) == b"the model's own bytes"


def test_the_file_swapped_for_a_link_out_is_refused(world):
    target = _checked(world)
    target.unlink()
    target.symlink_to(world / "outside" / "sub" / "data.bin")
    _refused(lambda: read_jail.read_checked(target), "is now a symbolic link")


def test_a_folder_swapped_for_a_link_out_is_refused(world):
    """The final name is a regular file, so O_NOFOLLOW alone would not see it: the opened descriptor's real path
    does."""
    target = _checked(world)
    (world / "model" / "sub").rename(world / "model" / "was-sub")
    (world / "model" / "sub").symlink_to(world / "outside" / "sub")
    _refused(lambda: read_jail.read_checked(target), "now leads to", str(world / "outside" / "sub" / "data.bin"))


def test_a_fifo_swapped_in_is_refused_without_waiting_for_a_writer(world):
    target = _checked(world)
    target.unlink()
    os.mkfifo(target)
    outcome: list = []
    reader = threading.Thread(target=lambda: outcome.append(_refused(lambda: read_jail.read_checked(target),
                                                                      "is now a FIFO")), daemon=True)
    reader.start()
    reader.join(10)
    if reader.is_alive():  # blocked in open(): release it, then fail
        with open(target, "wb"):
            pass
        pytest.fail("the reader waited on the FIFO for a writer")
    assert outcome, "the FIFO was not refused"


def test_a_path_the_jail_never_checked_opens_as_usual_links_and_all(world):
    """A user's own file (not a model's reference) may lie behind links: only checked paths are held to them."""
    link = world / "mine.bin"
    link.symlink_to(world / "outside" / "sub" / "data.bin")
    assert read_jail.read_checked(link) == SECRET


def test_a_gltf_whose_buffer_is_swapped_after_the_check_is_refused(world, monkeypatch):
    """End to end through the glTF reader: every URI is checked first, then read; the swap happens in between."""
    from wgpurender.core.models import gltf_io

    doc = triangle_gltf()
    data = base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1])
    doc["buffers"][0]["uri"] = "sub/data.bin"
    (world / "model" / "sub" / "data.bin").write_bytes(data)
    (world / "outside" / "sub" / "data.bin").write_bytes(data)  # a valid buffer: read silently before the fix
    model = write_gltf(world / "model" / "m.gltf", doc)
    check = read_jail.model_file

    def check_then_swap(*args, **kwargs):
        target = check(*args, **kwargs)
        (world / "model" / "sub").rename(world / "model" / "was-sub")
        (world / "model" / "sub").symlink_to(world / "outside" / "sub")
        return target

    monkeypatch.setattr(read_jail, "model_file", check_then_swap)
    _refused(lambda: gltf_io.read_document(model), "now leads to")


def test_a_texture_swapped_after_the_check_is_refused(world):
    from PIL import Image

    from wgpurender.core.scene.texture_pixels import load_image

    for top in ("model", "outside"):
        Image.fromarray(np.full((2, 2, 3), 200, np.uint8)).save(world / top / "sub" / "tex.png")
    texture = read_jail.model_file(world / "model" / "m.obj", "sub/tex.png", "m.mtl:3 map_Kd", encoded=False)
    assert load_image(texture)[0, 0, 0] == 200  # as checked: read
    texture.unlink()
    texture.symlink_to(world / "outside" / "sub" / "tex.png")
    _refused(lambda: load_image(texture), "is now a symbolic link")


MODELS = {
    "m.gltf": None,  # written from triangle_gltf below: gltf_io.read_document
    "m.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n",  # obj_simple
    "n.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",  # not the simple reader's: the records check, then trimesh
    "m.ply": (b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              b"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
}


@pytest.mark.parametrize("name", sorted(MODELS))
def test_a_scene_model_swapped_after_the_scene_loaded_is_refused(tmp_path, name):
    """The scene's check lets the model through (read_jail.outside); the model is swapped for a link to a copy
    outside the scene's folders before the mesh is read (load_mesh, as a render does after load_scene)."""
    from reliab_gen import scene_text

    from wgpurender.core.models.mesh import load_mesh
    from wgpurender.core.scene import load_scene

    data = MODELS[name] or json.dumps(triangle_gltf()).encode()
    for top in ("project", "outside"):
        (tmp_path / top).mkdir()
        (tmp_path / top / name).write_bytes(data)
    (tmp_path / "project" / "scene.toml").write_text(scene_text(name))
    scene = load_scene(tmp_path / "project" / "scene.toml")
    path = scene.models[0].path
    assert load_mesh(path).indices.size == 3  # as checked: read
    path.unlink()
    path.symlink_to(tmp_path / "outside" / name)
    _refused(lambda: load_mesh(path), "is now a symbolic link")


def _swap_for_link(path: Path, to: Path) -> None:
    path.unlink()
    path.symlink_to(to)


def test_an_environment_image_swapped_after_the_scene_loaded_is_refused(tmp_path):
    """A scene's [environment] .hdr is read when the maps are made, after the scene's check (load_scene)."""
    from reliab_gen import scene_text

    from wgpurender.core.files.hdr_io import encode_hdr
    from wgpurender.core.scene import load_scene

    for top in ("project", "outside"):
        (tmp_path / top).mkdir()
        (tmp_path / top / "sky.hdr").write_bytes(encode_hdr(np.full((4, 8, 3), 0.5)))
    (tmp_path / "project" / "scene.toml").write_text(scene_text(None, extra='[environment]\nhdr = "sky.hdr"\n'))
    environment = load_scene(tmp_path / "project" / "scene.toml").environment
    _swap_for_link(environment.hdr, tmp_path / "outside" / "sky.hdr")
    _refused(environment.radiance, "is now a symbolic link")


def test_a_material_library_swapped_after_its_check_is_refused(world, monkeypatch):
    """An OBJ's mtllib is checked (model_file), then read (parse_mtl): the swap happens in between."""
    from wgpurender.core.scene.file_materials import obj_mtl_entry

    obj = world / "model" / "m.obj"
    obj.write_text("mtllib m.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    for top in ("model", "outside"):
        (world / top / "m.mtl").write_text("newmtl red\nKd 1 0 0\n")
    check = read_jail.model_file

    def check_then_swap(model, uri, where, **kwargs):
        target = check(model, uri, where, **kwargs)
        if uri == "m.mtl":
            _swap_for_link(target, world / "outside" / "m.mtl")
        return target

    assert obj_mtl_entry(obj).name == "red"  # as checked: read
    monkeypatch.setattr(read_jail, "model_file", check_then_swap)
    _refused(lambda: obj_mtl_entry(obj), "is now a symbolic link")


def test_an_instances_file_swapped_after_its_check_is_refused(tmp_path, monkeypatch):
    """A scene's instances .npy is checked (read_jail.outside) and read in the same load: swapped in between."""
    from reliab_gen import scene_text

    from wgpurender.core.scene import load_scene

    for top in ("project", "outside"):
        (tmp_path / top).mkdir()
        np.save(tmp_path / top / "at.npy", np.zeros((2, 3)))
    (tmp_path / "project" / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    scene = tmp_path / "project" / "scene.toml"
    scene.write_text(scene_text("tri.obj").replace("unlit = true }", 'unlit = true }\ninstances = { file = "at.npy" }'))
    assert load_scene(scene).models[0].placements.count == 2  # as checked: read
    outside = read_jail.outside

    def check_then_swap(path, folders, *resolve):  # the scene's folder resolver, when the checker passes it
        verdict = outside(path, folders, *resolve)
        if Path(path).name == "at.npy":
            _swap_for_link(Path(path), tmp_path / "outside" / "at.npy")
        return verdict

    monkeypatch.setattr(read_jail, "outside", check_then_swap)
    _refused(lambda: load_scene(scene), "is now a symbolic link")
