"""The Python API (wgpurender.render / reference / compare ...): what a notebook user calls.

Expected values come from formulas here (the first triangle's vertex colours, the sRGB curve,
PSNR by hand) or from a second render made in this run on this machine, never from the API itself.
"""

from __future__ import annotations

import io
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image as PILImage

import wgpurender as w
from wgpurender.core.errors import UserError

REPO = Path(__file__).resolve().parent.parent
FINAL = REPO / "assets" / "scenes" / "final_subpass.toml"
TRIANGLE_NDC = np.array([[-0.8, -0.7], [0.7, -0.5], [-0.1, 0.8]])  # course step 2a; colours red, green, blue


def _expected_centre(width: int, height: int) -> tuple[int, int, np.ndarray]:
    """The pixel nearest the triangle's centroid and its colour: barycentric mix at the pixel centre, sRGB-encoded."""
    cx, cy = TRIANGLE_NDC.mean(axis=0)
    px, py = int((cx + 1) / 2 * width), int((1 - cy) / 2 * height)
    centre = np.array([(px + 0.5) / width * 2 - 1, 1 - (py + 0.5) / height * 2])
    a, b, c = TRIANGLE_NDC
    w1, w2 = np.linalg.solve(np.array([b - a, c - a]).T, centre - a)
    rgb = np.array([1 - w1 - w2, w1, w2])
    encoded = np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * rgb ** (1 / 2.4) - 0.055)
    return px, py, np.round(encoded * 255)


def test_import_is_cheap():
    """Importing the package and touching the API's names loads no GPU API and no mesh library."""
    code = ("import sys, wgpurender as w; w.reference, w.compare, w.Image, w.explain; "
            "print(sorted(m for m in ('wgpu', 'vulkan', 'trimesh', 'flip_evaluator') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_render_and_compare_are_plain_functions():
    """The API's render and compare are functions of wgpurender.api, not modules made callable."""
    import types

    from wgpurender import api

    assert w.render is api.render and w.compare is api.compare
    assert not isinstance(w.render, types.ModuleType) and not isinstance(w.compare, types.ModuleType)


def test_render_stage(ctx, tmp_path):
    img = w.render("triangle", size=(64, 48))
    assert isinstance(img, w.Image) and img.pixels.shape == (48, 64, 4) and img.pixels.dtype == np.uint8
    px, py, expected = _expected_centre(64, 48)
    assert np.abs(img.pixels[py, px, :3].astype(int) - expected).max() <= 1
    assert img.path == "wgpu" and img.plan is None and img.size == (64, 48)
    assert img.timings["frame_ms"] > 0 and img.timings["call_ms"] >= img.timings["frame_ms"]
    shown = np.asarray(PILImage.open(io.BytesIO(img._repr_png_())))
    assert np.array_equal(shown, img.pixels)
    assert np.array_equal(np.asarray(PILImage.open(img.save(tmp_path / "t.png"))), img.pixels)


def test_size_as_text_and_bad_sizes(ctx):
    assert w.render("clear", size="16x8").pixels.shape == (8, 16, 4)
    for bad in ("16by8", (0, 8), (16,), "x"):
        with pytest.raises(UserError, match="size"):
            w.render("clear", size=bad)


def test_unknown_stage_is_a_user_error(ctx):
    with pytest.raises(UserError, match="unknown stage 'nope'"):
        w.render("nope")


def test_render_scene_carries_its_plan(ctx):
    from wgpurender.wgpu_path.render import render_any

    img = w.render(FINAL, size=(96, 64), msaa=1)
    assert img.plan is not None and img.plan.size == (96, 64) and img.plan.msaa == 1
    assert "passes:" in img.plan.explain() and img.plan.explain() == w.explain(FINAL, size=(96, 64), msaa=1)
    again = render_any(str(FINAL), size=(96, 64), msaa=1, anisotropy="auto").pixels  # same machine: bit-identical
    assert np.array_equal(img.pixels, again)


def test_float_format_shows_srgb_encoded(ctx):
    img = w.render("clear", size=(8, 4), format="rgba16float")
    assert img.pixels.dtype == np.float16
    shown = np.asarray(PILImage.open(io.BytesIO(img._repr_png_())))
    linear = img.pixels[..., :3].astype(np.float64)
    encoded = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.clip(linear, 0, 1) ** (1 / 2.4) - 0.055)
    assert np.abs(shown[..., :3].astype(int) - np.round(encoded * 255)).max() <= 1


def test_reference_and_compare(ctx, tmp_path):
    pytest.importorskip("vulkan")
    import shutil

    if shutil.which("glslc") is None:
        pytest.skip("glslc not installed (apt install glslc)")
    wg = w.render("triangle", size=(64, 48))
    raw = w.reference("triangle", size=(64, 48))
    assert raw.path == "raw" and raw.pixels.shape == (48, 64, 4) and "call_ms" in raw.timings
    px, py, expected = _expected_centre(64, 48)
    assert np.abs(raw.pixels[py, px, :3].astype(int) - expected).max() <= 1
    result = w.compare(raw, wg)
    # both paths rasterise the same triangle on the same driver: at most 1/255 apart, FLIP tiny
    assert result.max_abs <= 1 and result.flip_mean < 0.01
    # paths and arrays work too; the numbers are the plain ones, computed here by hand
    a = np.full((10, 10, 4), 50, np.uint8)
    b = a.copy()
    b[0, 0, 1] = 54
    PILImage.fromarray(a).save(tmp_path / "a.png")
    r = w.compare(tmp_path / "a.png", b, flip=False)
    assert r.max_abs == 4 and r.over_2 == pytest.approx(0.01)
    assert r.psnr == pytest.approx(10 * np.log10(1 / (16 / 300 / 255**2)))
    with pytest.raises(UserError, match="expected a wgpurender.Image"):
        w.compare(a, [1, 2, 3])


def test_side_by_side_and_heatmap():
    a = w.Image(np.zeros((4, 6, 4), np.uint8), "a", "derived")
    b = np.full((3, 5, 4), 255, np.uint8)
    row = w.side_by_side(a, b, gap=2)
    assert row.pixels.shape == (4, 6 + 2 + 5, 4)
    assert (row.pixels[:3, 8:, :3] == 255).all() and (row.pixels[:, :6, :3] == 0).all()
    heat = w.heatmap(a, np.zeros((4, 6, 4), np.uint8))
    assert heat.pixels.shape[0] > 4 and (heat.pixels[:4, :6] == 0).all()  # equal: black, the scale below


def test_stage_lists():
    assert w.stage_names()[:1] == ["clear"] and "triangle" in w.stage_names()
    assert {"clear", "triangle", "msaa"} <= set(w.reference_stage_names())


def test_one_gpu_device_per_process():
    """Stage and scene renders share one adapter and device: count the devices requested."""
    code = f"""
import wgpu
calls = []
original = wgpu.GPUAdapter.request_device_sync
def counting(self, *a, **k):
    calls.append(1)
    return original(self, *a, **k)
wgpu.GPUAdapter.request_device_sync = counting
import wgpurender as w
w.render("triangle", size=(16, 8)); w.render("clear", size=(16, 8)); w.render({str(FINAL)!r}, size=(32, 24))
print(len(calls))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "1"
