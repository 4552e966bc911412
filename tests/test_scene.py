"""Scene files: a valid scene parses to the right values; each bad input is a UserError that names
the file, the line, the key and what is valid.

Matrices are checked against independent numpy constructions (explicit rotation
matrices, not transforms.rotate) to 1e-12. No GPU is used.
"""

from __future__ import annotations

import math
import re
import textwrap
from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.scene import MAX_LIGHTS, KeyLines, load_scene, parse_scene

TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n"
# 1x1 PNG (the scene only checks that texture files exist; the texture loader reads them)
PNG_1X1 = bytes.fromhex(
    "89504e470d0a1a0a0000000d4948445200000001000000010806000000"
    "1f15c4890000000d49444154789c63f8cfc0f01f0005000201a5f2e1f30000000049454e44ae426082"
)


@pytest.fixture()
def project(tmp_path: Path) -> Path:
    """tmp/scenes/ for scene files, tmp/models/tri.obj, tmp/textures/{albedo,normal,rough}.png."""
    (tmp_path / "scenes").mkdir()
    (tmp_path / "models").mkdir()
    (tmp_path / "textures").mkdir()
    (tmp_path / "models" / "tri.obj").write_text(TRIANGLE_OBJ)
    for name in ("albedo", "normal", "rough"):
        (tmp_path / "textures" / f"{name}.png").write_bytes(PNG_1X1)
    return tmp_path


CAMERA = """
[camera]
eye = [0, 1, 3]
target = [0, 0, 0]
"""


def write(project: Path, body: str, name: str = "scene.toml") -> Path:
    path = project / "scenes" / name
    path.write_text(textwrap.dedent(body).lstrip("\n"))
    return path


def line_of(path: Path, needle: str, occurrence: int = 1) -> int:
    """1-based line of the n-th line containing ``needle`` (the test's own independent count)."""
    hits = [i for i, line in enumerate(path.read_text().splitlines(), start=1) if needle in line]
    return hits[occurrence - 1]


def error_of(path: Path) -> str:
    with pytest.raises(UserError) as info:
        load_scene(path)
    return str(info.value)


def rot_y(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]])


def rot_x(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def rot_z(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def trs(t, r, s) -> np.ndarray:
    tm = np.eye(4)
    tm[:3, 3] = t
    return tm @ r @ np.diag([*s, 1.0])


VALID = """
description = "test scene"

[camera]
eye = [1, 2, 3]
target = [0, 0.5, 0]
fov_y = 50
near = 0.5
far = 20
convention = "glm-vulkan"

[materials.brick]
albedo_map = "../textures/albedo.png"   # a comment with = and [brackets]
normal_map = "../textures/normal.png"
roughness_map = "../textures/rough.png"
roughness = 0.7
sampler = { filter = "linear", mipmaps = true, anisotropy = 4, address_mode = "mirror-repeat" }

[[models]]
path = "../models/tri.obj"
material = "brick"
transform = { translate = [1, 2, 3], rotate = { axis = [0, 1, 0], degrees = 30 }, scale = 2 }

[[models]]
path = "../models/tri.obj"
material = { albedo_color = [0.5, 0.25, 1.0], unlit = true, uv_flip_v = true }
[models.transform]
rotate = { euler = [10, 20, 30] }
scale = [1, 2, 3]

[[models]]
path = "../models/tri.obj"
[models.transform]
matrix = [
  [1, 0, 0, 5],
  [0, 2, 0, 0],
  [0, 0, 3, 0],
  [0, 0, 0, 1],
]

[[lights]]
type = "directional"
direction = [0, -1, 0]
color = [1, 0.5, 0.25]
intensity = 3

[[lights]]
type = "point"
position = [1, 1, 1]

[render]
size = [64, 48]
msaa = 1
hdr = false
clear_color = [0.1, 0.2, 0.3]
output_format = "rgba8unorm"

[[post]]
effect = "tonemap"
exposure = 2

[[post]]
effect = "fxaa"
"""


def test_valid_scene_values(project):
    path = write(project, VALID)
    scene = load_scene(path)
    assert scene.description == "test scene"
    cam = scene.camera
    assert (cam.eye, cam.target, cam.up) == ((1, 2, 3), (0, 0.5, 0), (0, 1, 0))
    assert (cam.fov_y, cam.near, cam.far, cam.convention) == (50, 0.5, 20, "glm-vulkan")

    brick = scene.materials["brick"]
    assert brick.albedo_map == (project / "textures" / "albedo.png").resolve()
    assert brick.normal_map == (project / "textures" / "normal.png").resolve()
    assert brick.roughness_map == (project / "textures" / "rough.png").resolve()
    assert brick.roughness == 0.7 and not brick.unlit
    assert (brick.sampler.filter, brick.sampler.mipmaps, brick.sampler.anisotropy, brick.sampler.address_mode) == (
        "linear", True, 4, "mirror-repeat")
    assert brick.as_written("normal_map") == "../textures/normal.png"
    assert brick.sampler.spec().max_anisotropy == 4

    m0, m1, m2 = scene.models
    assert m0.path == (project / "models" / "tri.obj").resolve() and m0.material is brick
    np.testing.assert_allclose(m0.transform.array(), trs([1, 2, 3], rot_y(30), [2, 2, 2]), atol=1e-12)
    assert m1.material.albedo_color == (0.5, 0.25, 1.0, 1.0)
    assert m1.material.unlit and m1.material.uv_flip_v and m1.material.origin == "models[1].material (inline)"
    np.testing.assert_allclose(m1.transform.array(), trs([0, 0, 0], rot_z(30) @ rot_y(20) @ rot_x(10), [1, 2, 3]),
                               atol=1e-12)
    assert m2.material.name == "default" and not m2.material.textures
    np.testing.assert_array_equal(m2.transform.array(), [[1, 0, 0, 5], [0, 2, 0, 0], [0, 0, 3, 0], [0, 0, 0, 1]])

    sun, bulb = scene.lights
    assert (sun.type, sun.direction, sun.color, sun.intensity, sun.position) == (
        "directional", (0, -1, 0), (1, 0.5, 0.25), 3, None)
    assert (bulb.type, bulb.position, bulb.color, bulb.intensity) == ("point", (1, 1, 1), (1, 1, 1), 1.0)

    r = scene.render
    assert (r.size, r.msaa, r.hdr, r.clear_color, r.output_format) == ((64, 48), 1, False, (0.1, 0.2, 0.3, 1.0),
                                                                       "rgba8unorm")
    assert [(p.effect, dict(p.params)) for p in scene.post] == [
        ("tonemap", {"exposure": 2.0, "operator": "aces"}),
        ("fxaa", {"subpix": 0.75, "edge_threshold": 0.166, "edge_threshold_min": 0.0833}),
    ]
    assert scene.post[0].step().values["exposure"] == 2.0


def test_defaults(project):
    scene = load_scene(write(project, CAMERA))
    assert scene.models == () and scene.lights == () and scene.post == ()
    r = scene.render
    assert (r.size, r.msaa, r.hdr, r.output_format) == ((800, 600), 4, True, "rgba8unorm-srgb")
    assert scene.camera.convention == "wgpu" and scene.camera.fov_y == 45.0


def test_glm_vulkan_convention_is_flipped_back():
    """The source matrix has GLM's proj[1][1] negated (a point above the axis lands at clip y < 0, Vulkan's
    up); the matrix wgpu uses puts it at clip y > 0 and equals the plain right-handed perspective."""
    text = CAMERA.replace("[camera]", '[camera]\nconvention = "glm-vulkan"')
    vk = parse_scene(text).camera
    plain = parse_scene(CAMERA).camera
    f = 1 / math.tan(math.radians(45) / 2)
    assert vk.source_projection(1.5)[1, 1] == pytest.approx(-f)
    np.testing.assert_allclose(vk.projection(1.5), plain.projection(1.5), atol=0)
    above = np.array([0.0, 1.0, -5.0, 1.0])  # view space, above the view axis
    assert (vk.source_projection(1.5) @ above)[1] < 0 < (vk.projection(1.5) @ above)[1]


# -- errors ------------------------------------------------------------------
def test_unknown_key_names_file_line_and_valid_keys(project):
    path = write(project, CAMERA + "\n[render]\nmsaa = 4\nsizee = [10, 10]\n")
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, 'sizee')}: ")
    assert "unknown key 'sizee' in render" in msg
    assert "valid keys are clear_color, hdr, msaa, output_format, post_fuse, post_path, size" in msg


def test_unknown_key_in_second_model_inline_table(project):
    body = CAMERA + textwrap.dedent("""
        [[models]]
        path = "../models/tri.obj"

        [[models]]
        path = "../models/tri.obj"
        transform = { translate = [0, 0, 0], rotation = { axis = [0, 1, 0], degrees = 3 } }
        """)
    path = write(project, body)
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, 'rotation')}: ")
    assert "unknown key 'rotation' in models[1].transform: valid keys are matrix, rotate, scale, translate" in msg


def test_unknown_key_in_sub_table_after_array_header(project):
    body = CAMERA + textwrap.dedent("""
        [[models]]
        path = "../models/tri.obj"
        [models.transform]
        translate = [0, 0, 0]

        [[models]]
        path = "../models/tri.obj"
        [models.transform]
        scale = 2
        shear = 1
        """)
    path = write(project, body)
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, 'shear')}: ") and "models[1].transform" in msg


def test_unknown_top_level_table(project):
    path = write(project, CAMERA + "\n[lighting]\nambient = 0.1\n")
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, '[lighting]')}: ")
    assert ("unknown key 'lighting' in the top level: valid keys are camera, description, environment, lights, "
            "materials, models, post, render") in msg


def test_unknown_effect_lists_valid_names(project):
    path = write(project, CAMERA + '\n[[post]]\neffect = "tonemap"\n\n[[post]]\neffect = "bloom"\n')
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, 'bloom')}: ")
    assert "post[1]: unknown effect 'bloom': valid effects are fxaa, grayscale, sepia, sharpen, srgb, tonemap" in msg


def test_unknown_effect_parameter(project):
    path = write(project, CAMERA + '\n[[post]]\neffect = "vignette"\nstrength = 0.5\nradus = 0.3\n')
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, 'radus')}: ")
    assert "unknown key 'radus' in post[0]: valid keys are effect, strength, radius, softness" in msg


def test_effect_parameter_out_of_range(project):
    path = write(project, CAMERA + '\n[[post]]\neffect = "vignette"\nstrength = 5\n')
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, 'strength')}: ") and "strength must be in [0.0, 1.0], got 5" in msg


def test_srgb_effect_must_be_last(project):
    path = write(project, CAMERA + '\n[[post]]\neffect = "srgb"\n\n[[post]]\neffect = "fxaa"\n')
    assert "'srgb' must be the last effect" in error_of(path)


def test_missing_model_file_names_relative_and_resolved_path(project):
    path = write(project, CAMERA + '\n[[models]]\npath = "../models/nope.glb"\n')
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, 'nope.glb')}: ")
    assert "model file '../models/nope.glb' not found" in msg
    assert str((project / "models" / "nope.glb").resolve()) in msg
    assert "relative to the scene file's folder" in msg


def test_missing_texture_file(project):
    body = CAMERA + '\n[materials.wall]\nalbedo_map = "../textures/albedo.png"\nnormal_map = "textures/n.png"\n'
    path = write(project, body)
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, 'normal_map')}: ")
    assert "materials.wall.normal_map: texture 'textures/n.png' not found" in msg
    assert str(project / "scenes" / "textures" / "n.png") in msg


def test_unsupported_model_format(project):
    (project / "models" / "thing.blend").write_text("")
    path = write(project, CAMERA + '\n[[models]]\npath = "../models/thing.blend"\n')
    assert "'../models/thing.blend' is Blender, which cannot be loaded: convert it to glTF" in error_of(path)


def test_too_many_lights(project):
    light = '\n[[lights]]\ntype = "point"\nposition = [0, 1, 0]\n'
    path = write(project, CAMERA + light * (MAX_LIGHTS + 1))
    msg = error_of(path)
    assert msg.startswith(f"{path}:{line_of(path, '[[lights]]', MAX_LIGHTS + 1)}: ")
    assert f"{MAX_LIGHTS + 1} lights, but at most MAX_LIGHTS = {MAX_LIGHTS} are supported: remove 1" in msg
    load_scene(write(project, CAMERA + light * MAX_LIGHTS, "ok.toml"))  # exactly the limit is fine


@pytest.mark.parametrize(
    ("snippet", "needle", "expected"),
    [
        ('[render]\nmsaa = "4"\n', "msaa", "render.msaa must be an integer, got a string '4'"),
        ("[render]\nmsaa = 2\n", "msaa", "render.msaa must be one of 1, 4, got 2"),
        ("[render]\nhdr = 1\n", "hdr", "render.hdr must be true or false, got an integer 1"),
        ("[render]\nsize = [640]\n", "size", "render.size must be [width, height]"),
        ('[render]\noutput_format = "bgra8"\n', "output_format",
         "render.output_format must be one of rgba8unorm-srgb, rgba8unorm, rgba16float, got 'bgra8'"),
        ('[[lights]]\ntype = "spot"\nposition = [0, 0, 0]\n', "spot",
         "lights[0].type must be one of directional, point, got 'spot'"),
        ('[[lights]]\ntype = "point"\ndirection = [0, -1, 0]\n', "[[lights]]", "a point light needs 'position'"),
        ('[[lights]]\ntype = "directional"\ndirection = [0, 0, 0]\n', "direction =",
         "lights[0].direction must not be all zeros"),
        ("[[post]]\nexposure = 2\n", "[[post]]", "post[0] needs 'effect'"),
        ('[[post]]\neffect = "tonemap"\noperator = "filmic"\n', "operator",
         "operator must be one of aces, reinhard, got 'filmic'"),
        ('[[models]]\npath = "../models/tri.obj"\nmaterial = "stone"\n', "stone",
         "no material 'stone' (materials: none defined; define it as [materials.stone])"),
        ('[materials.m]\nsampler = { filter = "nearest", anisotropy = 8 }\n', "anisotropy",
         "anisotropy 8 needs filter = \"linear\""),
        ('[materials.m]\nunlit = "yes"\n', "unlit", "materials.m.unlit must be true or false, got a string 'yes'"),
        ("[materials.m]\nalbedo_color = [1, 0]\n", "albedo_color",
         "materials.m.albedo_color must be an array of 3 or 4 numbers"),
        ('[[models]]\npath = "../models/tri.obj"\ntransform = { matrix = [[1, 0, 0, 0]], scale = 2 }\n', "matrix",
         "matrix cannot be combined with scale"),
    ],
)
def test_wrong_values(project, snippet, needle, expected):
    path = write(project, CAMERA + "\n" + snippet)
    msg = error_of(path)
    assert expected in msg
    assert msg.startswith(f"{path}:{line_of(path, needle)}: "), msg


def test_camera_errors(project):
    path = write(project, "[camera]\neye = [0, 0]\ntarget = [0, 0, 0]\n")
    assert "camera.eye must be an array of 3 numbers" in error_of(path)
    path = write(project, "[camera]\neye = [0, 0, 1]\ntarget = [0, 0, 0]\nnear = 5\nfar = 1\n")
    assert f"{path}:5: camera.far (1.0) must be greater than camera.near (5.0)" in error_of(path)
    path = write(project, "[render]\nmsaa = 4\n")
    assert "the top level needs 'camera'" in error_of(path)


def test_invalid_toml_and_missing_file(project):
    path = write(project, "[camera\neye = 1\n")
    msg = error_of(path)
    assert msg.startswith(f"{path}: invalid TOML") and re.search(r"line 1", msg)
    with pytest.raises(UserError, match="scene file not found"):
        load_scene(project / "nope.toml")


def test_key_lines_skips_multiline_arrays_and_comments():
    text = textwrap.dedent("""\
        # header comment [not] a table
        [[models]]
        path = "a#b.obj"  # trailing = comment
        matrix = [
          [1, 0, 0, 0],
          [0, 1, 0, 0]
        ]
        [models.material]
        unlit = true
        [[models]]
        transform = { rotate = { axis = [0, 1, 0], degrees = 5 }, scale = 2 }
        """)
    keys = KeyLines(text)
    assert keys.line_of(("models", 0)) == 2
    assert keys.line_of(("models", 0, "path")) == 3
    assert keys.line_of(("models", 0, "matrix")) == 4
    assert keys.line_of(("models", 0, "material", "unlit")) == 9
    assert keys.line_of(("models", 1)) == 10
    assert keys.line_of(("models", 1, "transform", "rotate", "degrees")) == 11
    assert keys.line_of(("models", 1, "transform", "scale")) == 11
    assert keys.line_of(("models", 1, "unknown")) == 10  # falls back to the parent
    assert ("0, 1, 0, 0",) not in keys.lines  # a row of the array is not a table header
