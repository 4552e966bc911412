"""Numbers a user reads and rules a check applies, pinned by values from outside the code (issue 32 item 7).

Expected values come from the documentation (docs/guide.md's compare default, the calibration rule in the header
of assets/reference/tolerances.toml) or are worked out here by hand or by numpy's own percentile.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.verdict.tolerances import Metrics, calibrate
from wgpurender.core.view.frame_times import BenchmarkSpec, FrameRecorder, TitleCounter

REPO = Path(__file__).resolve().parent.parent


def test_compare_fails_above_the_documented_default_flip(monkeypatch, tmp_path):
    """docs/guide.md documents compare's default threshold; just above it exits 1, just below 0."""
    from wgpurender.cli import main
    from wgpurender.core.files.imageio import save_png
    from wgpurender.core.verdict import compare as compare_module

    documented = float(re.search(r"exceeds `flip_mean=([0-9.]+)`", (REPO / "docs" / "guide.md").read_text())[1])
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    save_png(a, np.zeros((4, 4, 4), np.uint8))
    save_png(b, np.full((4, 4, 4), 9, np.uint8))
    real = compare_module.compare_images
    for flip, code in ((documented * 1.02, 1), (documented * 0.98, 0)):
        monkeypatch.setattr(compare_module, "compare_images",
                            lambda x, y, f=flip, **_: dataclasses.replace(real(x, y, with_flip=False), flip_mean=f))
        assert main(["compare", str(a), str(b)]) == code


def test_the_calibration_rule_of_the_table_header():
    """The header of tolerances.toml: max_abs = worst + 1, at least 2 (lavapipe) or 1.5 x worst + 1 (gpu);
    changed, flip_mean = 2 x worst, at least 1% and 0.002."""
    worst = [Metrics(5, 0.03, 30, 0.004, 1000), Metrics(1, 0.001, 1, 0.0001, 1000)]
    assert calibrate(worst, "lavapipe") == {"max_abs": 6, "changed": 0.06, "flip_mean": 0.008}
    assert calibrate(worst, "gpu")["max_abs"] == 9  # ceil(7.5) + 1
    tiny = [Metrics(0, 0.0, 0, 0.0, 1000)]
    assert calibrate(tiny, "lavapipe") == {"max_abs": 2, "changed": 0.01, "flip_mean": 0.002}


def test_benchmark_frames_leave_out_the_warm_up():
    """Warm-up 1 s: frames ending at 0.5 and 1.0 s are warm-up; the intervals after are 100, 200, 300 ms."""
    rec = FrameRecorder(BenchmarkSpec(warmup_s=1.0, runtime_s=0.6))
    for now in (0.0, 0.5, 1.0, 1.1, 1.3):
        rec.frame_done(now)
        assert not rec.finished()
    rec.frame_done(1.6)
    assert rec.frame_ms == pytest.approx([100.0, 200.0, 300.0]) and rec.finished()


def test_benchmark_summary_statistics():
    """101 frames of 1..101 ms: mean 51 ms = 19.6 FPS, p50 51, p99 100.98 (numpy's 'weibull' percentile: the
    (n + 1) p rank that statistics.quantiles uses), min 1, max 101."""
    rec = FrameRecorder(BenchmarkSpec())
    rec.frame_ms = [float(v) for v in range(1, 102)]
    times = np.array(rec.frame_ms)
    p50, p99 = np.percentile(times, [50, 99], method="weibull")
    text = rec.summary()
    assert f"{1e3 / times.mean():.1f} FPS" in text and "19.6 FPS" in text
    assert f"p50 {p50:.3f}, p99 {p99:.3f}" in text and "p99 100.980" in text
    assert "min 1.000" in text and "max 101.000" in text and "101 frames in 5.15 s" in text


def test_title_fps_counts_each_frame_once():
    """Frames ending at 0, 0.2, 0.4 and 0.5 s (the title refreshes every 0.5 s): 3 frames in 500 ms, so
    166.67 ms and 6.0 FPS; the first call only starts the clock."""
    counter = TitleCounter("demo")
    titles = [counter.frame_done(now) for now in (0.0, 0.2, 0.4, 0.5)]
    assert titles == [None, None, None, "demo  |  6.0 FPS  166.67 ms"]


# glTF 2.0 specification, "samplers": minFilter codes -> (minification filter, mipmap filter or None)
SPEC_MIN_FILTERS = {9728: ("nearest", None), 9729: ("linear", None), 9984: ("nearest", "nearest"),
                    9985: ("linear", "nearest"), 9986: ("nearest", "linear"), 9987: ("linear", "linear")}


def _doc(material: dict, samplers: list | None = None, tmp: Path = Path("/nonexistent")):
    from wgpurender.core.models.gltf_io import GltfDocument

    texture = {"source": 0, **({"sampler": 0} if samplers else {})}
    return GltfDocument(tmp / "m.gltf", {"asset": {"version": "2.0"}, "images": [{"uri": "t.png"}],
                                         "textures": [texture], "samplers": samplers or [],
                                         "materials": [material]}, [])


@pytest.mark.parametrize(("code", "want"), SPEC_MIN_FILTERS.items())
def test_gltf_min_filter_codes(code, want):
    from wgpurender.core.scene.gltf_materials import sampler_spec

    doc = _doc({}, [{"minFilter": code, "magFilter": 9728}])
    spec, mips = sampler_spec(doc, doc.json["textures"][0])
    assert (spec.min_filter, mips) == (want[0], want[1] is not None) and spec.mag_filter == "nearest"
    if want[1] is not None:
        assert spec.mipmap_filter == want[1]


def test_gltf_normal_scale_and_emissive_strength():
    """normalTexture.scale 0.3 is the normal map's strength; emissiveFactor (0.5, 0.25, 1) x emissiveStrength 4
    (KHR_materials_emissive_strength) is (2, 1, 4)."""
    from wgpurender.core.scene.gltf_materials import file_material

    doc = _doc({"normalTexture": {"index": 0, "scale": 0.3}, "emissiveFactor": [0.5, 0.25, 1.0],
                "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}})
    material = file_material(doc, 0, "m", False, [])
    assert material.normal_strength == pytest.approx(0.3)
    assert material.emissive_color == pytest.approx((2.0, 1.0, 4.0))


def test_gltf_signed_normalized_integers():
    """glTF 2.0 accessor rules: a normalized signed component c is max(c / (2^(n-1) - 1), -1), an
    unsigned one c / (2^n - 1): BYTE -128 and -127 are -1, 64 is 64/127; SHORT 16384 is 16384/32767."""
    from wgpurender.core.models.gltf_io import GltfDocument, read_accessor

    data = np.array([-128, -127, 64, 127], np.int8).tobytes() + np.array([16384, -32768], "<i2").tobytes()
    doc = GltfDocument(Path("m.gltf"), {"bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 4},
                                                        {"buffer": 0, "byteOffset": 4, "byteLength": 4}],
                                        "accessors": [{"bufferView": 0, "componentType": 5120, "type": "SCALAR",
                                                       "count": 4, "normalized": True},
                                                      {"bufferView": 1, "componentType": 5122, "type": "SCALAR",
                                                       "count": 2, "normalized": True}]}, [data])
    np.testing.assert_allclose(read_accessor(doc, 0).ravel(), [-1.0, -1.0, 64 / 127, 1.0], rtol=1e-6)
    np.testing.assert_allclose(read_accessor(doc, 1).ravel(), [16384 / 32767, -1.0], rtol=1e-6)


def test_gltf_node_transform_scales_before_it_moves():
    """glTF: a node's matrix is T * R * S. The point (1, 0, 0) of a node scaled by (2, 1, 1), turned 90 degrees
    about z and moved by (1, 0, 0): scaled (2, 0, 0), turned (0, 2, 0), moved (1, 2, 0). Turning before scaling
    would give (1, 1, 0); moving before either, (0, 4, 0)."""
    from wgpurender.core.models.gltf_geometry import node_matrix

    half = np.sqrt(0.5)
    m = node_matrix({"translation": [1.0, 0.0, 0.0], "scale": [2.0, 1.0, 1.0], "rotation": [0.0, 0.0, half, half]})
    np.testing.assert_allclose(m @ [1.0, 0.0, 0.0, 1.0], [1.0, 2.0, 0.0, 1.0], atol=1e-12)


@pytest.mark.parametrize(("adapter_type", "want"), [("DiscreteGPU", "compute"), ("IntegratedGPU", "fragment"),
                                                    ("CPU", "fragment"), ("", "fragment")])
def test_the_automatic_post_path_per_adapter(adapter_type, want):
    """docs/scenes.md: post_path "auto" is compute on a discrete GPU, fragment on every other adapter (an
    integrated GPU, a CPU driver, the browser page's unknown adapter)."""
    from wgpurender.core.plan import AdapterFacts, resolve_plan

    plan = resolve_plan(REPO / "assets" / "scenes" / "final_subpass.toml", AdapterFacts(adapter_type, name="x"))
    assert {p.path for p in plan.post_passes} == {want}


def test_the_browser_page_draws_the_fragment_post_path():
    """The exported page's plan is made for the browser's adapter (unknown type): fragment post passes."""
    from wgpurender.core.plan import resolve_plan
    from wgpurender.webpage.recorder import BROWSER

    plan = resolve_plan(REPO / "assets" / "scenes" / "final_subpass.toml", BROWSER)
    assert plan.post_passes and {p.path for p in plan.post_passes} == {"fragment"}


def _push_block(shader: str) -> list[tuple[str, str]]:
    """(type, name) of each member of a GLSL shader's push_constant block, in declaration order."""
    text = (REPO / "shaders_glsl" / shader).read_text()
    body = re.search(r"layout\(push_constant\)\s*uniform\s+\w+\s*\{(.*?)\}", text, re.S)[1]
    return re.findall(r"^\s*(\w+)\s+(\w+)\s*;", body, re.M)


def test_raw_push_constants_follow_the_shaders_blocks():
    """The raw path's push constants, packed as the GLSL blocks declare them (std430: tightly packed scalars,
    a vec4 at 0 and the uint after it at 16): cube3d.vert's Draw, post_fxaa.frag's and post_sharpen.frag's Params."""
    import struct

    from wgpurender.core.course.effects import EffectStep
    from wgpurender.raw_path.device.ubo import DRAW_SIZE, pack_draw
    from wgpurender.raw_path.post.neighbourhood import push_constants

    assert _push_block("cube3d.vert") == [("vec4", "tint"), ("uint", "object_index")]
    assert pack_draw((0.25, 0.5, 0.75, 1.0), 7) == struct.pack("<4fI", 0.25, 0.5, 0.75, 1.0, 7)
    assert DRAW_SIZE == 20
    for shader, effect in (("post_fxaa.frag", "fxaa"), ("post_sharpen.frag", "sharpen")):
        members = _push_block(shader)
        assert all(kind == "float" for kind, _ in members)
        values = {name: 0.125 * (k + 1) for k, (_, name) in enumerate(members)}
        step = EffectStep(effect, tuple(reversed(list(values.items()))))  # the order of params must not matter
        assert push_constants(step) == struct.pack(f"<{len(members)}f", *values.values())


def test_dynamic_offsets_are_aligned():
    """Copies of a uniform block in one buffer sit at multiples of the device's minimum offset alignment (at
    least 16 bytes): a 144-byte block at 256 on a 256-aligned device, 160 at 16 where 16 is allowed."""
    from wgpurender.raw_path.device.ubo import dynamic_stride, pack_many

    assert dynamic_stride(144, 256) == 256 and dynamic_stride(300, 256) == 512 and dynamic_stride(144, 4) == 144
    assert dynamic_stride(150, 1) == 160
    assert pack_many([b"ab", b"c"], 4) == b"ab\x00\x00c\x00\x00\x00"


def test_the_report_shows_each_paths_times_in_its_own_column():
    """A step timed wgpu GPU 1.25 / frame 2.5 ms and raw GPU 3.75 / frame 5.0 ms: the GPU-time row reads
    1.250 then 3.750 (wgpu, raw Vulkan: the header's order), the frame-time row 2.500 then 5.000; a path without
    timestamps reads n/a."""
    from wgpurender.report.page import _numbers
    from wgpurender.report.steps import Step
    from wgpurender.report.timings import Timing

    step = Step("3d", "3d", "4", "", [], timing={"wgpu": Timing(2.5, 1.25), "raw": Timing(5.0, 3.75)})
    html = _numbers(step)
    assert '<th class="label">wgpu</th><th class="label">raw Vulkan</th>' in html
    rows = dict(re.findall(r'data-metric="([\w-]+)">(.*?)</tr>', html))
    cells = {key: re.findall(r'<td class="value">([^<]*)</td>', row) for key, row in rows.items()}
    assert cells["gpu-ms"] == ["1.250 ms", "3.750 ms"] and cells["frame-ms"] == ["2.500 ms", "5.000 ms"]
    step.timing["raw"] = Timing(5.0, None)
    assert re.findall(r'<td class="value">([^<]*)</td>', dict(re.findall(
        r'data-metric="([\w-]+)">(.*?)</tr>', _numbers(step)))["gpu-ms"]) == ["1.250 ms", "n/a"]


def test_report_timing_medians(monkeypatch):
    """A run of frames 3, 1, 2 ms with GPU times 30, 10, 20 ms: Timing(frame 2, GPU 20); no GPU samples: None."""
    from types import SimpleNamespace

    from wgpurender.report import timings

    monkeypatch.setattr(timings, "measure", lambda runner, frames, warmup: runner)
    assert timings._timing(SimpleNamespace(frame=[3.0, 1.0, 2.0], gpu=[30.0, 10.0, 20.0])) == timings.Timing(2.0, 20.0)
    assert timings._timing(SimpleNamespace(frame=[3.0, 1.0, 2.0], gpu=[])) == timings.Timing(2.0, None)


def test_the_recorder_samples_frame_k_at_k_over_fps():
    """An animated target recorded at 4 fps for 1 s: frames drawn at t = 0, 0.25, 0.5, 0.75 and one sample each,
    sample k holding the upload made at t = k / 4."""
    from types import SimpleNamespace

    from wgpurender.webpage.record import _record_frames

    recording = SimpleNamespace(calls=[])
    encoder = SimpleNamespace(finish=lambda: None)
    ctx = SimpleNamespace(device=SimpleNamespace(create_command_encoder=lambda label: encoder),
                          queue=SimpleNamespace(submit=lambda buffers: None))
    seen = []

    def record(enc, target, t):
        seen.append(t)
        recording.calls += [{"m": "writeBuffer", "a": [7, 0, {"#": int(t * 100)}]}, {"m": "draw", "a": [3]}]

    template, samples = _record_frames(ctx, recording, record, None, fps=4, seconds=1.0)
    assert seen == [0.0, 0.25, 0.5, 0.75]
    assert samples == [[0], [25], [50], [75]]
