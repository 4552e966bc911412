"""Third-party FBX files as their tools wrote them (issue 30 item 3): two of assimp's own test models (BSD-3,
tests/data/assimp/README.md), each drawn textured and lit on both paths.

- ``box_orphant_embedded_texture.fbx``: ASCII FBX 7.5 (3ds Max), a unit cube placed by its node, its texture
  (a 256x256 grey grid, TGA) embedded in the file, its path an absolute/outside one. The reference texture is
  decoded here from the file's own base64 ``Content`` (not through assimp), the cube's size and place from its
  ``Vertices`` and ``Lcl Translation``: the grid lines must land where the camera puts u = line / 256 on the face
  the camera looks at, and its texels must be lit (diffuse lower bound) or ambient-only by the light's side.
- ``spider.fbx``: binary FBX 7.4, 19 meshes over 4 materials, each naming a JPEG by an absolute Windows path of
  the exporting machine (``D:\\projects\\...``); the JPEGs are shipped beside it.
"""

from __future__ import annotations

import base64
import io
import re

import numpy as np
import pytest
from test_gltf_render import render, srgb_decode, srgb_encode

from wgpurender.core.course.shading import AMBIENT

pytest.importorskip("pyassimp")  # noqa: E402 (skips without libassimp too)

DATA = __import__("pathlib").Path(__file__).parent / "data" / "assimp"
BOX = "box_orphant_embedded_texture.fbx"
SIZE = (256, 256)
FOV = 40.0
EYE_Z = 2.0


def _numbers(text: str) -> list[float]:
    return [float(v) for v in text.split(",") if v.strip()]


def box_facts() -> tuple[np.ndarray, float, np.ndarray]:
    """(centre, half size, texture RGB) from the ASCII file: node translation, Vertices, the embedded Content."""
    text = (DATA / BOX).read_text(encoding="utf-8", errors="replace")
    vertices = _numbers(re.search(r"Vertices: \*\d+ \{\s*a: ([^}]*)\}", text).group(1))
    translation = _numbers(re.search(r'P: "Lcl Translation", "Lcl Translation", "", "A",([-\d.e,]+)', text)
                           .group(1))
    assert re.search(r'P: "UnitScaleFactor", "double", "Number", "",100\b', text)  # metres: no conversion
    assert re.search(r'P: "UpAxis", "int", "Integer", "",1\b', text)  # Y up: no axis change
    content = re.search(r'Content: ,\s*"([A-Za-z0-9+/=]+)"', text).group(1)
    from PIL import Image

    texture = np.asarray(Image.open(io.BytesIO(base64.b64decode(content))).convert("RGB"))
    return np.asarray(translation), float(np.abs(vertices).max()), texture


def box_scene(tmp_path, light_z: float):
    """The camera on the face's axis at EYE_Z, looking at the cube's centre; one directional light along z."""
    centre, _, _ = box_facts()
    (tmp_path / BOX).write_bytes((DATA / BOX).read_bytes())
    text = (f"[camera]\neye = [{centre[0]}, {centre[1]}, {EYE_Z}]\ntarget = [{centre[0]}, {centre[1]}, 0]\n"
            f"fov_y = {FOV}\nnear = 0.1\nfar = 10\n[render]\nsize = [{SIZE[0]}, {SIZE[1]}]\nmsaa = 1\nhdr = false\n"
            f'clear_color = [0, 0, 0, 1]\n[[models]]\npath = "{BOX}"\n[[lights]]\ntype = "directional"\n'
            f"direction = [0, 0, {light_z}]\nintensity = 1.0\n")
    path = tmp_path / "box.toml"
    path.write_text(text)
    return path


def screen(x: float, y: float, z: float) -> tuple[float, float]:
    """(column, row) of a world point for the box camera (on the z axis through the centre, square image)."""
    centre, _, _ = box_facts()
    scale = 1.0 / ((EYE_Z - z) * np.tan(np.radians(FOV / 2)))
    return ((x - centre[0]) * scale + 1) / 2 * SIZE[0], (1 - (y - centre[1]) * scale) / 2 * SIZE[1]


def line_centres(texture: np.ndarray) -> list[float]:
    """u (0..1) of the grid's inner vertical lines: runs of texels brighter than the background along a background
    row, each at its run's centre."""
    row = texture[96, :, 0].astype(int)  # texel row 96: between two horizontal lines
    bright = [c for c in range(8, texture.shape[1] - 8) if row[c] > int(np.median(row)) + 10]
    runs: list[list[int]] = []
    for c in bright:
        if runs and c == runs[-1][-1] + 1:
            runs[-1].append(c)
        else:
            runs.append([c])
    return [(np.mean(run) + 0.5) / texture.shape[1] for run in runs]


@pytest.mark.parametrize("which", ("wgpu", "raw"))
def test_box_grid_lines_land_where_the_file_puts_them(ctx, tmp_path, which):
    """Along a row between two horizontal grid lines, the bright columns inside the front face are the texture's
    line texels mapped through the face's u = 0..1 (either way round: the grid is symmetric to a texel)."""
    centre, half, texture = box_facts()
    lines = line_centres(texture)
    assert len(lines) == 3  # the 4x4 grid's inner lines
    image = render(ctx, box_scene(tmp_path, -1.0), which, SIZE)
    z = centre[2] + half
    _, row = screen(0, centre[1] + half * 0.25, z)  # v = 3/8: between lines
    left, _ = screen(centre[0] - half, 0, z)
    right, _ = screen(centre[0] + half, 0, z)
    profile = image[int(row), :, :3].astype(int).sum(axis=1)
    inside = range(int(left) + 4, int(right) - 4)
    background = np.median([profile[c] for c in inside])
    bright = [c for c in inside if profile[c] > background + 15]
    assert bright, (which, profile[int(left):int(right)].tolist())
    want = [left + (right - left) * t for u in lines for t in (u, 1 - u)]
    for u in lines:
        at = [left + (right - left) * u, left + (right - left) * (1 - u)]
        assert any(min(abs(b + 0.5 - w) for w in at) <= 1.5 for b in bright), (which, u, at, bright)
    for b in bright:  # nothing bright elsewhere
        assert min(abs(b + 0.5 - w) for w in want) <= 2.0, (which, b, want)


@pytest.mark.parametrize("which", ("wgpu", "raw"))
def test_box_front_face_is_lit_only_by_a_light_on_its_side(ctx, tmp_path, which):
    """A background texel of the front face (texel colour x Kd 1, from the embedded image): with the light on its
    side at least ambient + diffuse (n.l = 1; the specular term only adds), with the light behind the cube only
    the ambient term."""
    centre, half, texture = box_facts()
    background = srgb_decode(np.median(texture[96, :, :], axis=0))
    col, row = screen(centre[0] - half * 0.25, centre[1] + half * 0.25, centre[2] + half)  # u, v = 3/8: no line
    lit = render(ctx, box_scene(tmp_path, -1.0), which, SIZE)[int(row), int(col), :3].astype(float)
    dark = render(ctx, box_scene(tmp_path, 1.0), which, SIZE)[int(row), int(col), :3].astype(float)
    assert np.all(lit >= srgb_encode(background * (1 + np.asarray(AMBIENT))) - 3), (which, lit)
    assert np.abs(dark - srgb_encode(background * np.asarray(AMBIENT))).max() <= 3, (which, dark)


SPIDER_TEXTURES = ("drkwood2.jpg", "wal67ar_small.jpg", "engineflare1.jpg", "SpiderTex.jpg")


def spider_scene(tmp_path, material: str = "", light_y: float = -1.0):
    for f in ("spider.fbx", *SPIDER_TEXTURES):
        (tmp_path / f).write_bytes((DATA / f).read_bytes())
    text = ("[camera]\neye = [-15, 250, 0]\ntarget = [-15, 0, -1]\nfov_y = 50\nnear = 1\nfar = 1000\n[render]\n"
            "size = [128, 128]\nmsaa = 1\nhdr = false\nclear_color = [0, 0, 0, 1]\n"
            f'[[models]]\npath = "spider.fbx"\n{material}\n[[lights]]\ntype = "directional"\n'
            f"direction = [0, {light_y}, 0]\nintensity = 1.0\n")
    path = tmp_path / "spider.toml"
    path.write_text(text)
    return path


def test_spider_draws_four_materials_with_the_textures_beside_it(tmp_path, capsys):
    """Each of the file's 4 materials is its own draw; each texture's absolute path of the exporting machine is
    not followed, the file of that name beside the model is read, and --explain says so."""
    from wgpurender.cli import main

    assert main(["render", str(spider_scene(tmp_path)), "--explain"]) == 0
    out = capsys.readouterr().out
    for name, texture in zip(("BeinTex", "Skin", "Augentex", "HLeibTex"), SPIDER_TEXTURES, strict=True):
        assert f"FBX material '{name}'" in out, name
        assert f"is outside the model's folder: read {texture} beside the model" in out, texture
    assert "D:" not in "".join(line for line in out.splitlines() if "albedo_map =" in line)


@pytest.mark.parametrize("which", ("wgpu", "raw"))
def test_spider_renders_textured_and_lit(ctx, tmp_path, which):
    """Against the same spider in a plain grey scene material (same triangles, same light): the same pixels are
    covered, and they carry the textures' colours (the JPEGs' own mean colours are warm: R > B), not grey; a
    light from below leaves the top-down view far darker than a light from above."""
    from PIL import Image

    warm = [np.asarray(Image.open(DATA / t).convert("RGB"), float).reshape(-1, 3).mean(0) for t in SPIDER_TEXTURES]
    assert all(m[0] > m[2] for m in warm)
    textured = render(ctx, spider_scene(tmp_path), which, (128, 128))[..., :3].astype(float)
    grey = render(ctx, spider_scene(tmp_path, "material = { albedo_color = [0.5, 0.5, 0.5, 1] }"), which,
                  (128, 128))[..., :3].astype(float)
    from_below = render(ctx, spider_scene(tmp_path, light_y=1.0), which, (128, 128))[..., :3].astype(float)
    covered = textured.max(axis=2) > 0
    assert covered.sum() > 500 and np.array_equal(covered, grey.max(axis=2) > 0)
    assert np.median(grey[covered][:, 0] - grey[covered][:, 2]) <= 1  # grey stays grey (the ambient is bluish)
    assert np.median(textured[covered][:, 0] - textured[covered][:, 2]) >= 8  # the textures' warm colours
    assert textured[covered].mean() > 3 * from_below[covered].mean()


def test_spider_wgpu_equals_raw_within_one_run(ctx, tmp_path):
    scene = spider_scene(tmp_path)
    np.testing.assert_array_equal(render(ctx, scene, "wgpu", (128, 128)), render(ctx, scene, "raw", (128, 128)))
