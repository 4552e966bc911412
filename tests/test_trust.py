"""Tests that catch what a tired developer's one-line change breaks (issue 24, item 7), where the earlier suite
checked only that something plausible came out:

- the API's path: ``w.render`` is the wgpu path's image and ``w.reference`` the raw path's (on lavapipe the two
  draw the course's stages identically, so comparing pixels alone cannot tell them apart: each path's renderer is
  replaced by one that marks its pixels, and the mark must come out of the right function);
- the tolerance table's driver class, on the names this machine's adapters really report;
- the raw window's present-mode names -> VkPresentModeKHR values (from the Vulkan specification, not the module);
- depth compare where ``less`` and ``less-equal`` differ: coplanar geometry, on both paths.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import wgpurender as w

REPO = Path(__file__).resolve().parent.parent
needs_glslc = pytest.mark.skipif(shutil.which("glslc") is None, reason="the raw path needs glslc")


def _mark(pixels: np.ndarray, value: int) -> np.ndarray:
    out = np.array(pixels, copy=True)
    out[0, 0, :3] = value
    return out


# --- the API's path --------------------------------------------------------------------------------------------

def test_render_is_the_wgpu_paths_image_and_reference_the_raw_paths(ctx, monkeypatch):
    import wgpurender.raw_path as raw_path
    import wgpurender.wgpu_path.render as wgpu_render

    real_wgpu, real_raw = wgpu_render.render_stage, raw_path.render_reference

    def wgpu_marked(*args, **kwargs):
        result = real_wgpu(*args, **kwargs)
        return type(result)(_mark(result.pixels, 11), result.frame_ms, result.adapter, result.plan)

    monkeypatch.setattr(wgpu_render, "render_stage", wgpu_marked)
    monkeypatch.setattr(raw_path, "render_reference", lambda *a, **k: _mark(real_raw(*a, **k), 22))
    image = w.render("triangle", size=(32, 24))
    assert image.path == "wgpu" and image.pixels[0, 0, :3].tolist() == [11, 11, 11]
    assert ctx.adapter.info["device"] in image.adapter and "raw Vulkan" not in image.adapter
    if shutil.which("glslc"):
        ref = w.reference("triangle", size=(32, 24))
        assert ref.path == "raw" and ref.pixels[0, 0, :3].tolist() == [22, 22, 22]
        assert "raw Vulkan" in ref.adapter


def test_a_scene_render_is_the_wgpu_paths_and_carries_its_plan(ctx, monkeypatch):
    import wgpurender.wgpu_path.scene as scene_render

    real = scene_render.render_plan

    def marked(*args, **kwargs):
        result = real(*args, **kwargs)
        return type(result)(_mark(result.pixels, 33), result.frame_ms, result.adapter, result.plan)

    monkeypatch.setattr(scene_render, "render_plan", marked)
    image = w.render(REPO / "assets" / "scenes" / "unlit.toml", size=(40, 30))
    assert image.path == "wgpu" and image.pixels[0, 0, :3].tolist() == [33, 33, 33]
    assert image.plan is not None and image.plan.size == (40, 30)


# --- the tolerance table's driver class -----------------------------------------------------------------------

LAVAPIPE_NAMES = ("llvmpipe (LLVM 15.0.6, 256 bits)", "llvmpipe (LLVM 17.0.6, 128 bits)", "LLVMPIPE (LLVM 19.1.7)")
GPU_NAMES = ("NVIDIA H100 80GB HBM3", "NVIDIA H200", "AMD Radeon RX 7900 XTX (RADV NAVI31)",
             "Intel(R) Arc(tm) A770 Graphics (DG2)", "Apple M2", "SwiftShader Device (Subzero)")


@pytest.mark.parametrize("name", LAVAPIPE_NAMES + GPU_NAMES)
def test_driver_class_of_the_names_drivers_report(name):
    from wgpurender.core.verdict.tolerances import driver_class

    assert driver_class(name) == ("lavapipe" if name in LAVAPIPE_NAMES else "gpu")


def test_this_machines_adapters_get_the_class_their_type_says(ctx):
    """lavapipe reports 'llvmpipe (...)' as its device name: a class matched on 'lavapipe' silently used the
    looser GPU row on every lavapipe run."""
    from wgpurender.core.verdict.tolerances import driver_class, load_table, tolerance

    info = ctx.adapter.info
    expected = "lavapipe" if info["adapter_type"] == "CPU" else "gpu"
    assert driver_class(info["device"]) == expected
    table = load_table()
    name = next(iter(table["references"])) if "references" in table else None
    if name is not None and expected == "lavapipe":
        assert tolerance(name, driver_class(info["device"]), table).driver_class == "lavapipe"


@needs_glslc
def test_the_raw_paths_device_gets_the_class_its_type_says():
    from wgpurender.core.verdict.tolerances import driver_class
    from wgpurender.raw_path.device.context import get_vulkan

    vk = get_vulkan()
    assert driver_class(vk.device_name) == ("lavapipe" if vk.device_type == "CPU" else "gpu")


# --- the raw window's present modes ----------------------------------------------------------------------------

# VkPresentModeKHR in the Vulkan specification (vk.xml): IMMEDIATE 0, MAILBOX 1, FIFO 2, FIFO_RELAXED 3.
SPEC_PRESENT_MODES = {"immediate": 0, "mailbox": 1, "fifo": 2, "fifo-relaxed": 3}


def test_present_mode_names_map_to_the_specifications_values():
    from wgpurender.raw_path.window.swapchain import MODE_NAMES, PRESENT_MODES

    assert {k: int(v) for k, v in PRESENT_MODES.items()} == SPEC_PRESENT_MODES
    assert {int(k): v for k, v in MODE_NAMES.items()} == {v: k for k, v in SPEC_PRESENT_MODES.items()}


def test_check_present_mode_returns_the_value_of_the_name_asked():
    from wgpurender.raw_path.window.swapchain import SurfaceOffer, check_present_mode

    fields = SurfaceOffer.__dataclass_fields__
    offer = SurfaceOffer(**{f: () for f in fields} | {"present_modes": tuple(SPEC_PRESENT_MODES)})
    for name, value in SPEC_PRESENT_MODES.items():
        assert check_present_mode(offer, name) == value


from xvfb import xvfb_display  # noqa: E402,F401 - the shared Xvfb fixture "display"


@pytest.mark.parametrize("mode", ["fifo", "immediate"])
def test_the_raw_window_creates_its_swapchain_with_the_mode_asked(display, monkeypatch, mode):
    """The VkPresentModeKHR handed to vkCreateSwapchainKHR, not just that a window opened."""
    from wgpurender.raw_path import window as raw_window

    monkeypatch.setenv("DISPLAY", display)
    used = []
    real = raw_window.create_swapchain

    def spy(ctx, surface, offer, size, present_mode, *args, **kwargs):
        used.append((int(present_mode), offer.present_modes))
        return real(ctx, surface, offer, size, present_mode, *args, **kwargs)

    monkeypatch.setattr(raw_window, "create_swapchain", spy)
    try:
        raw_window.run_raw_window("clear-pass", (32, 32), present_mode=mode, frames=1)
    except w.UserError as err:  # not offered by this surface: the one-line refusal, before any swapchain
        assert "is not offered" in str(err) and not used
        return
    assert used and all(value == SPEC_PRESENT_MODES[mode] for value, _ in used)


# --- depth compare on coplanar geometry ------------------------------------------------------------------------

QUAD = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n"
COPLANAR = """
[camera]
eye = [0.0, 0.0, 3.0]
target = [0.0, 0.0, 0.0]
near = 0.5
far = 10.0

[materials.first]
albedo_color = [1.0, 0.0, 0.0]
unlit = true

[materials.second]
albedo_color = [0.0, 1.0, 0.0]
unlit = true

[[models]]  # drawn first
path = "quad.obj"
material = "first"

[[models]]  # the same plane: its depths equal the stored ones, so compare "less" (and "greater") rejects it
path = "quad.obj"
material = "second"

[render]
size = [32, 24]
msaa = 1
hdr = false
clear_color = [0.0, 0.0, 1.0, 1.0]
output_format = "rgba8unorm"
"""


@pytest.fixture
def coplanar(tmp_path):
    (tmp_path / "quad.obj").write_text(QUAD)
    (tmp_path / "scene.toml").write_text(COPLANAR)
    return tmp_path / "scene.toml"


def _centre(image) -> list[int]:
    h, wd = image.pixels.shape[:2]
    return image.pixels[h // 2, wd // 2, :3].tolist()


def test_coplanar_geometry_keeps_what_was_drawn_first_on_the_wgpu_path(ctx, coplanar):
    image = w.render(coplanar)
    assert image.plan.pipelines[0].depth_compare in ("less", "greater")
    assert _centre(image) == [255, 0, 0]


def test_coplanar_geometry_keeps_what_was_drawn_first_with_reverse_z(ctx, coplanar):
    from wgpurender.wgpu_path.scene import render_plan

    plan = w.plan(coplanar).with_knobs(reverse_z=True)
    assert plan.pipelines[0].depth_compare == "greater"
    pixels = render_plan(ctx, plan, 0.0).pixels
    assert pixels[12, 16, :3].tolist() == [255, 0, 0]


@needs_glslc
def test_coplanar_geometry_keeps_what_was_drawn_first_on_the_raw_path(coplanar):
    assert _centre(w.reference(coplanar)) == [255, 0, 0]


# --- the tolerance check at its bounds ---------------------------------------------------------------------------

def test_a_tolerance_fails_just_over_each_bound_and_passes_at_it():
    from wgpurender.core.verdict.tolerances import Metrics, Tolerance

    bound = Tolerance("x", "lavapipe", max_abs=2, changed=0.01, flip_mean=0.002, measured="", bounded_by="",
                      provisional=False)
    pixels = 10_000
    at = Metrics(max_abs=2, changed=0.01, changed_pixels=100, flip_mean=0.002, pixels=pixels)
    assert bound.exceeded(at) == []
    over = {"max_abs": Metrics(3, 0.01, 100, 0.002, pixels), "changed": Metrics(2, 0.0101, 101, 0.002, pixels),
            "flip_mean": Metrics(2, 0.01, 100, 0.00201, pixels)}
    words = {"max_abs": "max diff", "changed": "changed pixels", "flip_mean": "FLIP mean"}
    for metric, metrics in over.items():
        lines = bound.exceeded(metrics)
        assert len(lines) == 1 and lines[0].startswith(words[metric]), (metric, lines)
