"""Issue 15's cases, one test each: every bad input gives exit 2 and exactly one line on stderr that says what,
where (file and line, or JSON path) and how to fix it; the cases with a correct answer give that answer."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image
from reliab_gen import run_cli, scene_text, triangle_gltf, write_gltf


def _one_line(err: str) -> str:
    lines = err.splitlines()
    assert len(lines) == 1, f"expected one stderr line, got {len(lines)}:\n{err}"
    assert "Traceback" not in err
    return lines[0]


def _render(tmp_path, text: str, *extra: str) -> tuple[int, str, str]:
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    return run_cli("render", scene, "-o", tmp_path / "out.png", *extra)


def _fails(tmp_path, text: str, *needles: str, extra: tuple[str, ...] = ()) -> str:
    code, _, err = _render(tmp_path, text, *extra)
    line = _one_line(err)
    assert code == 2, err
    for needle in needles:
        assert needle in line, line
    assert not (tmp_path / "out.png").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
    return line


# --- glTF JSON of the wrong shape -------------------------------------------------------------------------------

def _broken(doc: dict, key: str, value) -> dict:
    doc[key] = value
    return doc


GLTF_SHAPES = {
    "buffers-of-strings": (lambda d: _broken(d, "buffers", ["x"]), "$.buffers[0] must be an object"),
    "buffer-uri-number": (lambda d: _broken(d, "buffers", [{"uri": 5, "byteLength": 4}]),
                          "$.buffers[0].uri must be a string, got 5"),
    "buffers-number": (lambda d: _broken(d, "buffers", 5), "$.buffers must be an array, got 5"),
    "materials-of-strings": (lambda d: _broken(d, "materials", ["x"]), "$.materials[0] must be an object"),
    "textures-of-strings": (lambda d: _broken(d, "textures", ["x"]), "$.textures[0] must be an object"),
    "images-of-strings": (lambda d: _broken(d, "images", ["x"]), "$.images[0] must be an object"),
}


@pytest.mark.parametrize("case", sorted(GLTF_SHAPES))
def test_gltf_of_the_wrong_shape_names_its_json_path(tmp_path, case):
    mutate, needle = GLTF_SHAPES[case]
    write_gltf(tmp_path / "model.gltf", mutate(triangle_gltf()))
    line = _fails(tmp_path, scene_text(), "malformed glTF file", "model.gltf", needle, "re-export")
    assert "schema" in line


# --- transforms ---------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("node, needle", [
    ({"scale": [0, 1, 1]}, "singular transform"),
    ({"matrix": [1e308] * 16}, "beyond float32's range"),
])
def test_singular_or_huge_gltf_node_transform_is_refused(tmp_path, node, needle):
    write_gltf(tmp_path / "model.gltf", triangle_gltf(normals=True, node=node))
    _fails(tmp_path, scene_text(), "model.gltf", needle)


# --- OBJ records and float32 range --------------------------------------------------------------------------------

OBJ_TRIANGLE = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\n"


def test_obj_vt_with_one_coordinate_names_file_and_line(tmp_path):
    (tmp_path / "model.obj").write_text(OBJ_TRIANGLE + "vt 0 0\nvt 0.5\nvt 1 1\nf 1/1 2/2 3/3\n")
    _fails(tmp_path, scene_text("model.obj"), "model.obj:5:", "'vt 0.5'", "needs 2 numbers", "vt u v")


def test_obj_coordinates_beyond_float32_are_refused_not_dropped(tmp_path):
    # 1e39 is finite in float64 (the old check) and infinite in float32 (what the GPU gets)
    (tmp_path / "model.obj").write_text("v -1 -1 0\nv 1e39 -1 0\nv 0 1 0\nf 1 2 3\n")
    _fails(tmp_path, scene_text("model.obj"), "model.obj", "vertex position", "float32")


def test_missing_material_library_prints_nothing_and_renders(tmp_path):
    (tmp_path / "model.obj").write_text("mtllib missing.mtl\nusemtl m\n" + OBJ_TRIANGLE + "f 1 2 3\n")
    code, out, err = _render(tmp_path, scene_text("model.obj"))
    assert code == 0 and err == ""
    pixels = np.asarray(Image.open(tmp_path / "out.png"))
    assert (pixels[12, 16, :3] == 255).all()  # the unlit white triangle covers the centre


# --- paths --------------------------------------------------------------------------------------------------------

def test_nul_in_model_path_is_one_line(tmp_path):
    _fails(tmp_path, scene_text("mo\\u0000del.obj"), "scene.toml:", "models[0].path", "control character",
           "\\x00")


def test_nul_in_texture_path_is_one_line(tmp_path):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    text = scene_text(None) + '\n[materials.m]\nalbedo_map = "a\\u0000b.png"\n'
    _fails(tmp_path, text, "scene.toml:", "materials.m.albedo_map", "control character")


def test_nul_in_a_material_library_texture_path_is_a_user_error(tmp_path):
    from wgpurender.core.errors import UserError
    from wgpurender.core.scene import load_scene

    (tmp_path / "model.mtl").write_bytes(b"newmtl m\nmap_Kd a\x00b.png\n")
    (tmp_path / "model.obj").write_text("mtllib model.mtl\nusemtl m\n" + OBJ_TRIANGLE + "f 1 2 3\n")
    scene = tmp_path / "scene.toml"  # the model names no material: it draws with the OBJ's, read when the scene loads
    scene.write_text(scene_text(None) + '\n[[models]]\npath = "model.obj"\n')
    with pytest.raises(UserError, match=r"model\.mtl:2: texture path 'a\\x00b\.png' contains a control character"):
        load_scene(scene)  # the scene reads the OBJ's own material (was a ValueError from Path.resolve)


def test_newline_in_a_value_is_escaped_onto_one_line(tmp_path):
    line = _fails(tmp_path, scene_text("two\\nlines.obj"), "models[0].path")
    assert "\\n" in line


# --- camera values with degenerate consequences --------------------------------------------------------------------

def _camera(eye="[0, 0, 3]", up="[0, 1, 0]", near="0.1") -> str:
    return f"eye = {eye}\ntarget = [0, 0, 0]\nup = {up}\nnear = {near}\nfar = 20.0\n"


def test_near_plane_too_small_for_the_depth_buffer(tmp_path):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    # depth at distance 3 is 1 - 1e-7/3, which rounds to 1.0 in float32: the old blank image
    line = _fails(tmp_path, scene_text(camera=_camera(near="1e-7")), "scene.toml:5:", "camera.near", "depth")
    least = 3.0 * 2.0**-20
    assert f"near >= {least:.3g}" in line


def test_near_plane_at_the_limit_still_draws_the_triangle(tmp_path):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    code, _, err = _render(tmp_path, scene_text(camera=_camera(near=repr(3.0 * 2.0**-20 * 1.01))))
    assert code == 0, err
    assert (np.asarray(Image.open(tmp_path / "out.png"))[12, 16, :3] == 255).all()


def test_up_vector_that_overflows_is_refused(tmp_path):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    _fails(tmp_path, scene_text(camera=_camera(up="[0, 1e200, 0]")), "scene.toml:4:", "camera.up", "float32")


def test_far_eye_reports_its_own_cause_not_the_up_vector(tmp_path):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    line = _fails(tmp_path, scene_text(camera=_camera(eye="[0, 0, 1e308]")), "scene.toml:2:", "camera.eye",
                  "float32")
    assert "parallel" not in line


def test_up_parallel_to_the_view_is_still_reported_as_such(tmp_path):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    _fails(tmp_path, scene_text(camera=_camera(up="[0, 0, 1]")), "camera.up", "parallel")


# --- post-effect parameters: the error sits at the parameter's own line ----------------------------------------------

def test_bad_post_parameter_is_reported_at_its_own_line(tmp_path):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    text = scene_text() + "\n[[post]]\neffect = \"vignette\"\nstrength = 0.4\nradius = -7\n"
    radius_line = text.splitlines().index("radius = -7") + 1
    line = _fails(tmp_path, text, f"scene.toml:{radius_line}:", "radius")
    assert f"scene.toml:{radius_line - 1}:" not in line


# --- CLI numbers ----------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
@pytest.mark.parametrize("command", ["render 3d -o", "reference triangle -o", "demo triangle --screenshot"])
def test_animation_time_must_be_finite(tmp_path, value, command):
    code, _, err = run_cli(*command.split(), tmp_path / "x.png", f"--time={value}")
    assert code == 2 and "--time" in _one_line(err) and "finite" in err
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("value, needle", [("nan", "finite"), ("0", "above 0"), ("-1", "above 0")])
def test_compare_gain_must_be_positive_and_finite(tmp_path, value, needle):
    image = np.zeros((4, 4, 3), np.uint8)
    for name in ("a.png", "b.png"):
        Image.fromarray(image).save(tmp_path / name)
    code, _, err = run_cli("compare", tmp_path / "a.png", tmp_path / "b.png", "--heatmap", tmp_path / "h.png",
                           f"--gain={value}")
    assert code == 2 and "--gain" in _one_line(err) and needle in err
    assert not (tmp_path / "h.png").exists()


# --- images: bit depth --------------------------------------------------------------------------------------------

def test_compare_of_a_16_bit_png_with_its_own_8_bit_version_is_exact(tmp_path):
    wide = (np.arange(64 * 64).reshape(64, 64) * 16).astype(np.uint16)  # 0..65520
    Image.fromarray(wide).save(tmp_path / "wide.png")
    assert Image.open(tmp_path / "wide.png").mode == "I;16"
    Image.fromarray(np.round(wide / 257.0).astype(np.uint8)).save(tmp_path / "narrow.png")
    code, out, err = run_cli("compare", tmp_path / "wide.png", tmp_path / "narrow.png")
    assert code == 0 and err == ""
    values = {k.strip(): v for k, v in (line.split(":") for line in out.splitlines())}
    assert float(values["psnr"]) == float("inf") and float(values["max_abs"]) == 0  # was 4.8 dB: clipped at 255
