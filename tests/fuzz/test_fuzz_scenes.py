"""Fuzzed scene files through ``wgpurender render``: every case is a clean render or one clean error line."""

from __future__ import annotations

import pytest
from harness import check, render_argv, reset_folder, run_case
from hypothesis import given
from hypothesis import strategies as st
from reliab_gen import triangle_gltf, write_gltf
from strategies import ASSETS, fuzz_settings, link_assets, mutated_text, number_text, toml_value, vector

SCENES = sorted((ASSETS / "scenes").glob("*.toml"))
EFFECTS = ["tonemap", "fxaa", "vignette", "grayscale", "sepia", "sharpen", "srgb", "bloom"]
MODELS = ["model.gltf", "models/brick_cube.obj", "models/brick_torus.glb", "models/mirrored_quad.glb", "nope.obj"]


@pytest.fixture
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("scene")


def _case(folder, text: str, label: str) -> None:
    reset_folder(folder)
    link_assets(folder)
    write_gltf(folder / "model.gltf", triangle_gltf())
    (folder / "out").mkdir()
    scene = folder / "scene.toml"
    scene.write_text(text)
    output = folder / "out" / "out.png"
    outcome = run_case(render_argv(scene, output), output, scene, label)
    check(outcome, f"{outcome}: {label}\n{text}")


def _maybe(draw, key: str, value: st.SearchStrategy) -> str:
    return f"{key} = {draw(value)}\n" if draw(st.booleans()) else ""


@st.composite
def scene_text(draw) -> str:
    """A scene built key by key: mostly valid structure, values from the edges."""
    good = st.sampled_from(["[0, 0.5, 3]", "[2, 1, 2]", "[0, 0, -3]"])
    text = "[camera]\n"
    text += f"eye = {draw(st.one_of(good, vector()))}\n"
    text += f"target = {draw(st.one_of(st.just('[0, 0, 0]'), vector()))}\n"
    text += _maybe(draw, "up", st.one_of(st.just("[0, 1, 0]"), vector()))
    for key in ("fov_y", "near", "far"):
        text += _maybe(draw, key, number_text)
    text += _maybe(draw, "convention", st.sampled_from(['"wgpu"', '"glm-vulkan"', '"dx"']))
    text += "\n[render]\n"
    text += _maybe(draw, "msaa", st.sampled_from(["1", "4", "2", "0"]))
    text += _maybe(draw, "hdr", st.sampled_from(["true", "false", "1"]))
    text += _maybe(draw, "output_format", st.sampled_from(['"rgba8unorm"', '"rgba8unorm-srgb"', '"rgba16float"']))
    text += _maybe(draw, "clear_color", st.one_of(st.just("[0.05, 0.1, 0.2]"), vector(4)))
    for _ in range(draw(st.integers(0, 2))):
        text += "\n[[models]]\n" + f'path = "{draw(st.sampled_from(MODELS))}"\n'
        text += "material = { " + ", ".join(draw(st.lists(_material_item(), max_size=3))) + " }\n"
        if draw(st.booleans()):
            text += "transform = { " + draw(_transform()) + " }\n"
    for _ in range(draw(st.integers(0, 2))):
        kind = draw(st.sampled_from(["directional", "point", "spot"]))
        text += f'\n[[lights]]\ntype = "{kind}"\n'
        text += f"{'direction' if kind == 'directional' else 'position'} = {draw(vector())}\n"
        text += _maybe(draw, "intensity", number_text) + _maybe(draw, "color", vector())
    for _ in range(draw(st.integers(0, 2))):
        text += f'\n[[post]]\neffect = "{draw(st.sampled_from(EFFECTS))}"\n'
        text += _maybe(draw, draw(st.sampled_from(["exposure", "strength", "radius", "amount", "subpix"])),
                       toml_value)
    return text


@st.composite
def _material_item(draw) -> str:
    key = draw(st.sampled_from(["albedo_color", "roughness", "unlit", "uv_flip_v", "albedo_map", "sampler"]))
    value = {
        "albedo_color": st.one_of(st.just("[0.9, 0.8, 0.6]"), vector(4)),
        "roughness": number_text,
        "unlit": st.sampled_from(["true", "false", "0"]),
        "uv_flip_v": st.sampled_from(["true", "false"]),
        "albedo_map": st.sampled_from(['"textures/brick_albedo.png"', '"textures/none.png"', '"models"', '""']),
        "sampler": st.sampled_from(["{ anisotropy = 16, mipmaps = false }", "{ filter = \"nearest\" }",
                                    "{ anisotropy = 4, filter = \"nearest\" }", "{ address_mode = \"clamp\" }"]),
    }[key]
    return f"{key} = {draw(value)}"


@st.composite
def _transform(draw) -> str:
    kind = draw(st.sampled_from(["translate", "scale", "rotate", "matrix"]))
    if kind == "matrix":
        rows = ", ".join(draw(vector(4)) for _ in range(4))
        return f"matrix = [{rows}]"
    if kind == "rotate":
        return f"rotate = {{ axis = {draw(vector())}, degrees = {draw(number_text)} }}"
    return f"{kind} = {draw(st.one_of(vector(), number_text) if kind == 'scale' else vector())}"


@fuzz_settings(ci=12, long=2500)
@given(text=scene_text())
def test_generated_scenes(folder, text):
    _case(folder, text, "generated scene")


@fuzz_settings(ci=8, long=1500)
@given(data=st.data())
def test_mutated_repository_scenes(folder, data):
    source = data.draw(st.sampled_from(SCENES))
    text = data.draw(mutated_text(source.read_text()))
    # the repository's scenes name ../models and ../textures: put the scene one level down
    text = text.replace('"../', '"')
    _case(folder, text, f"mutated {source.name}")
