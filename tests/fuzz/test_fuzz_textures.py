"""Fuzzed PNG textures (any mode, bit depth and size; byte mutations of the repository's textures) on a textured
quad: a clean render or one clean error."""

from __future__ import annotations

import io

import numpy as np
import pytest
from harness import check, render_argv, reset_folder, run_case
from hypothesis import given
from hypothesis import strategies as st
from PIL import Image
from reliab_gen import SCENE_CAMERA
from strategies import ASSETS, fuzz_settings, link_assets, mutated_bytes

TEXTURES = sorted((ASSETS / "textures").glob("*.png"))
MODES = {"1": np.bool_, "L": np.uint8, "LA": np.uint8, "P": np.uint8, "RGB": np.uint8, "RGBA": np.uint8,
         "I;16": np.uint16}


@pytest.fixture
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("texture")


@st.composite
def png_bytes(draw) -> bytes:
    """A PNG of a random mode, size 1..48 and content (noise or flat), saved by Pillow."""
    mode = draw(st.sampled_from(sorted(MODES)))
    w, h = draw(st.integers(1, 48)), draw(st.integers(1, 48))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    channels = {"LA": 2, "RGB": 3, "RGBA": 4}.get(mode, 1)
    top = {"1": 2, "I;16": 65536}.get(mode, 256)
    values = rng.integers(0, top, (h, w, channels) if channels > 1 else (h, w))
    if draw(st.booleans()):
        values[...] = values.flat[0]
    if mode == "1":
        image = Image.fromarray(values.astype(bool))
    elif mode == "P":
        image = Image.fromarray(values.astype(np.uint8), "L").convert("P")
    else:
        image = Image.fromarray(values.astype(MODES[mode]))
    buffer = io.BytesIO()
    image.save(buffer, format="PNG", compress_level=draw(st.integers(0, 9)))
    return buffer.getvalue()


@st.composite
def scene_for(draw) -> str:
    """The textured quad, the texture in one of the three roles, a sampler at its edges."""
    role = draw(st.sampled_from(["albedo_map", "normal_map", "roughness_map"]))
    sampler = draw(st.sampled_from(["{}", "{ mipmaps = false }", "{ filter = \"nearest\" }",
                                    "{ anisotropy = 16 }", "{ address_mode = \"mirror-repeat\" }"]))
    lights = '[[lights]]\ntype = "directional"\ndirection = [0, 0, -1]\n'
    return (f"[camera]\n{SCENE_CAMERA}\n[render]\nsize = [40, 30]\nclear_color = [0.2, 0.4, 0.6]\n\n"
            f"[materials.m]\n{role} = \"texture.png\"\nsampler = {sampler}\n\n"
            f"[[models]]\npath = \"models/mirrored_quad.glb\"\nmaterial = \"m\"\n\n{lights}")


def _case(folder, texture: bytes, scene_text: str, label: str) -> None:
    reset_folder(folder)
    link_assets(folder)
    (folder / "out").mkdir()
    (folder / "texture.png").write_bytes(texture)
    scene = folder / "scene.toml"
    scene.write_text(scene_text)
    output = folder / "out" / "out.png"
    outcome = run_case(render_argv(scene, output), output, scene, label)
    check(outcome, f"{outcome}: {label}")


@fuzz_settings(ci=8, long=1100)
@given(texture=png_bytes(), scene=scene_for())
def test_generated_pngs(folder, texture, scene):
    _case(folder, texture, scene, "generated png")


@fuzz_settings(ci=6, long=1100)
@given(data=st.data(), scene=scene_for())
def test_mutated_repository_textures(folder, data, scene):
    source = data.draw(st.sampled_from(TEXTURES))
    _case(folder, data.draw(mutated_bytes(source.read_bytes())), scene, f"mutated {source.name}")
