"""A slow window frame says once why, and what to change (issue 15: vulkan_tutorial_28.toml took 19.9 s a frame
at 96x72 on lavapipe with nothing telling the user why). The clock is passed in: no timing in tests."""

from __future__ import annotations

from pathlib import Path

import pytest

from wgpurender import slow_frames
from wgpurender.scene import load_scene

SCENES = Path(__file__).resolve().parents[1] / "assets" / "scenes"
CPU = {"adapter_type": "CPU", "device": "llvmpipe (LLVM 15.0.7, 256 bits)", "description": "Mesa"}
GPU = {"adapter_type": "DiscreteGPU", "device": "NVIDIA H200", "description": "550.54"}


class _Ctx:
    def __init__(self, info):
        self.adapter = type("Adapter", (), {"info": info})()


class _Drawable:
    def __init__(self, scene_name):
        self.scene = load_scene(SCENES / scene_name)
        self.plan = type("Plan", (), {"msaa": self.scene.render.msaa})()


def _frames(ctx, drawable, times):
    return [slow_frames.tick(ctx, drawable, (96, 72), now=t) for t in times]


def test_anisotropy_without_mips_on_a_cpu_driver_is_named_once(capsys):
    drawable = _Drawable("vulkan_tutorial_28.toml")
    notes = _frames(_Ctx(CPU), drawable, [0.0, 19.9, 39.8, 59.7])
    said = [n for n in notes if n]
    assert len(said) == 1 and notes[1] == said[0]  # the first slow frame, once
    for needle in ("19.9 s", "96x72", "anisotropic filtering (16x) without mip maps", "CPU driver",
                   "anisotropy = 1 or mipmaps = true"):
        assert needle in said[0]
    assert capsys.readouterr().err.strip() == said[0]


def test_fast_frames_say_nothing(capsys):
    almost = slow_frames.SLOW_FRAME_SECONDS * 0.99
    notes = _frames(_Ctx(CPU), _Drawable("vulkan_tutorial_28.toml"), [0.0, 0.5, 1.0, 1.0 + almost])
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
