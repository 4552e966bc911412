"""FBX models (issue 30 item 3) through assimp, on both paths, checked against the numbers written into the file.

The FBX file is made at run time: an OBJ written here is exported by assimp's own command-line tool
(``assimp export``, Debian's assimp-utils) as ASCII FBX 7.5, and its GlobalSettings are then rewritten here to the
axes and units of a Blender export (Z up, front -Y, UnitScaleFactor 1: centimetres). Expectations come from the
vertex numbers and those settings: a vertex (x cm, 0, z cm) of a Z-up file lands at (x / 100, z / 100, 0) m.
"""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest
from gltf_gen import pixel_of
from test_gltf_render import PATHS, SIZE, render

pytest.importorskip("pyassimp")  # noqa: E402 (skips without libassimp too: pyassimp raises ImportError then)
if shutil.which("assimp") is None:
    pytest.skip("assimp's command-line tool (assimp-utils) writes the test's FBX file", allow_module_level=True)

TEXELS = np.array([[[230, 30, 30, 255], [30, 200, 40, 255]], [[40, 60, 230, 255], [240, 240, 240, 255]]], np.uint8)
X0, Z0, X1, Z1 = -140.0, -120.0, 150.0, 130.0  # centimetres, the quad in the file's X-Z plane (Z up)
BLENDER_AXES = {"UpAxis": 2, "UpAxisSign": 1, "FrontAxis": 1, "FrontAxisSign": -1, "CoordAxis": 0,
                "CoordAxisSign": 1, "UnitScaleFactor": 1}


def write_fbx(tmp_path, settings: dict) -> str:
    from PIL import Image

    Image.fromarray(TEXELS, "RGBA").save(tmp_path / "tex.png")
    Image.fromarray(np.full((2, 2, 4), (128, 128, 255, 255), np.uint8), "RGBA").save(tmp_path / "nrm.png")
    (tmp_path / "q.mtl").write_text("newmtl skin\nKd 1 1 1\nmap_Kd tex.png\nmap_Bump nrm.png\n")
    # OBJ: v = 0 at the bottom of the image; the quad faces -Y in the file (toward the viewer after Z-up -> Y-up)
    (tmp_path / "q.obj").write_text(
        f"mtllib q.mtl\nv {X0} 0 {Z0}\nv {X1} 0 {Z0}\nv {X1} 0 {Z1}\nv {X0} 0 {Z1}\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 -1 0\nusemtl skin\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")
    subprocess.run(["assimp", "export", "q.obj", "q.fbx", "-ffbxa"], cwd=tmp_path, check=True, capture_output=True)
    text = (tmp_path / "q.fbx").read_text()
    for key, value in settings.items():
        text, n = re.subn(rf'(P: "{key}", "(?:int|double)", "(?:Integer|Number)", "", )[-\d.]+', rf"\g<1>{value}",
                          text)
        assert n == 1, key
    (tmp_path / "q.fbx").write_text(text)
    return "q.fbx"


def scene(tmp_path, model: str, lights: bool = False):
    text = ("[camera]\neye = [0, 0, 2]\ntarget = [0, 0, 0]\nfov_y = 90\nnear = 0.1\nfar = 10\n\n[render]\n"
            f"size = [{SIZE[0]}, {SIZE[1]}]\nmsaa = 1\nhdr = false\nclear_color = [0, 0, 0, 1]\n\n"
            f'[[models]]\npath = "{model}"\n')
    if lights:
        text += '\n[[lights]]\ntype = "directional"\ndirection = [0, 0, -1]\nintensity = 1.0\n'
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("which", PATHS)
def test_fbx_in_centimetres_z_up_lands_where_its_numbers_say(ctx, tmp_path, which):
    """Edges at x = X0/100 .. X1/100 and y = Z0/100 .. Z1/100 (one pixel either side covered / not covered), and
    the diffuse texture's quarters in place (each quarter's strongest channel is its texel's): UVs, v flip,
    the material's map and the light (a directional light along -z, the quad facing +z after the axis change)."""
    image = render(ctx, scene(tmp_path, write_fbx(tmp_path, BLENDER_AXES), lights=True), which)
    covered = image[..., :3].max(axis=2) > 10
    x0, y0, x1, y1 = X0 / 100, Z0 / 100, X1 / 100, Z1 / 100
    step = 4 / SIZE[1]  # one pixel in scene units at z = 0
    for x, y, inside in ((x0 + step, 0, True), (x0 - step, 0, False), (x1 - step, 0, True), (x1 + step, 0, False),
                         (0, y1 - step, True), (0, y1 + step, False), (0, y0 + step, True), (0, y0 - step, False)):
        col, row = pixel_of(x, y, SIZE)
        assert covered[int(row), int(col)] == inside, (which, x, y, inside)
    for row in range(2):
        for col in range(2):
            x = x0 + (x1 - x0) * (0.25 + 0.5 * col)
            y = y1 - (y1 - y0) * (0.25 + 0.5 * row)  # texel row 0 is the top of the image
            c, r = pixel_of(x, y, SIZE)
            got = image[int(r), int(c), :3].astype(int)
            want = TEXELS[row, col, :3].astype(int)
            if want.min() > 200:
                assert got.min() > 0.6 * got.max() > 0, (which, row, col, got)  # white: grey, lit
            else:
                assert int(np.argmax(got)) == int(np.argmax(want)), (which, row, col, got.tolist(), want.tolist())


def test_fbx_in_metres_y_up_is_taken_as_is(tmp_path):
    """UnitScaleFactor 100 (metres) and Y up: positions unchanged apart from the file's own numbers / 1."""
    from wgpurender.core.models.mesh import load_mesh

    settings = {**BLENDER_AXES, "UpAxis": 1, "FrontAxis": 2, "FrontAxisSign": 1, "UnitScaleFactor": 100}
    mesh = load_mesh(tmp_path / write_fbx(tmp_path, settings), generate_tangents=False)
    assert np.allclose(mesh.positions.min(0), [X0, 0, Z0]) and np.allclose(mesh.positions.max(0), [X1, 0, Z1])
    from wgpurender.core.scene.load import load_scene  # the material: the scene's reader

    write_fbx(tmp_path, settings)
    (material,) = load_scene(scene(tmp_path, "q.fbx")).models[0].file_materials.materials
    assert (material.albedo_map.name, material.normal_map.name) == ("tex.png", "nrm.png")


def test_fbx_explain_takes_diffuse_and_normal_maps(tmp_path, capsys):
    from wgpurender.cli import main

    assert main(["render", str(scene(tmp_path, write_fbx(tmp_path, BLENDER_AXES), lights=True)), "--explain"]) == 0
    out = capsys.readouterr().out
    assert "FBX material 'skin'" in out and "albedo_map = 'tex.png'" in out and "normal_map = 'nrm.png'" in out
    assert "up +z turned to +y, UnitScaleFactor 1 cm per unit -> metres (x0.01)" in out


def test_a_broken_fbx_is_one_line(tmp_path):
    from wgpurender.core.errors import UserError
    from wgpurender.core.models.mesh import load_mesh

    (tmp_path / "bad.fbx").write_bytes(b"Kaydara FBX Binary  \x00\x1a\x00" + b"\xff" * 40)
    with pytest.raises(UserError) as info:
        load_mesh(tmp_path / "bad.fbx")
    assert "\n" not in str(info.value) and "bad.fbx" in str(info.value)
