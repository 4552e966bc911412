"""A slow window frame says once why, and what to change (issue 15: vulkan_tutorial_28.toml took 19.9 s a frame
at 96x72 on lavapipe with nothing telling the user why). The clock is passed in: no timing in tests."""

from __future__ import annotations

from pathlib import Path

import pytest

from wgpurender.core.scene import load_scene
from wgpurender.core.view import slow_frames

SCENES = Path(__file__).resolve().parents[1] / "assets" / "scenes"
CPU = {"adapter_type": "CPU", "device": "llvmpipe (LLVM 15.0.7, 256 bits)", "description": "Mesa"}
GPU = {"adapter_type": "DiscreteGPU", "device": "NVIDIA H200", "description": "550.54"}


class _Ctx:
    def __init__(self, info):
        self.adapter = type("Adapter", (), {"info": info})()


ASSETS = SCENES.parent
# The tutorial's chapter-28 sampler (one mip level, anisotropy 16) on the repository's own model and texture, so the
# test needs nothing from ../shared.
ANISOTROPIC_NO_MIPS = f"""
[camera]
eye = [2.0, 2.0, 2.0]
target = [0.0, 0.0, 0.0]

[[models]]
path = "{ASSETS / 'models' / 'brick_cube.obj'}"
material.albedo_map = "{ASSETS / 'textures' / 'brick_albedo.png'}"
material.unlit = true
material.sampler = {{ filter = "linear", mipmaps = false, anisotropy = 16 }}

[render]
msaa = 1
"""


class _Drawable:
    def __init__(self, scene):
        self.scene = load_scene(scene if isinstance(scene, Path) else SCENES / scene)
        self.plan = type("Plan", (), {"msaa": self.scene.render.msaa})()


@pytest.fixture
def anisotropic_scene(tmp_path):
    path = tmp_path / "anisotropic_no_mips.toml"
    path.write_text(ANISOTROPIC_NO_MIPS)
    return path


def _frames(ctx, drawable, times):
    return [slow_frames.tick(ctx, drawable, (96, 72), now=t) for t in times]


def test_anisotropy_without_mips_on_a_cpu_driver_is_named_once(capsys, anisotropic_scene):
    drawable = _Drawable(anisotropic_scene)
    notes = _frames(_Ctx(CPU), drawable, [0.0, 19.9, 39.8, 59.7])
    said = [n for n in notes if n]
    assert len(said) == 1 and notes[1] == said[0]  # the first slow frame, once
    for needle in ("19.9 s", "96x72", "anisotropic filtering (16x) without mip maps", "CPU driver",
                   "anisotropy = 1 or mipmaps = true"):
        assert needle in said[0]
    assert capsys.readouterr().err.strip() == said[0]


def test_fast_frames_say_nothing(capsys, anisotropic_scene):
    almost = slow_frames.SLOW_FRAME_SECONDS * 0.99
    notes = _frames(_Ctx(CPU), _Drawable(anisotropic_scene), [0.0, 0.5, 1.0, 1.0 + almost])
    assert notes == [None] * 4 and capsys.readouterr().err == ""


def test_the_first_frame_is_not_judged():
    """It pays for shader compilation: only the gap between two frames counts."""
    assert _frames(_Ctx(CPU), _Drawable("final.toml"), [100.0]) == [None]


@pytest.mark.parametrize("info, needle", [(CPU, "4x MSAA on a CPU driver"), (GPU, "make the window smaller")])
def test_other_slow_scenes_get_the_next_likely_cause(info, needle):
    drawable = _Drawable("final.toml")
    assert drawable.scene.render.msaa == 4
    note = _frames(_Ctx(info), drawable, [0.0, 5.0])[1]
    assert note and needle in note
