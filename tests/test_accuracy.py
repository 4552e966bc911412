"""bench accuracy (wgpurender/bench/accuracy*.py): resolve filter, Pareto front, the run's files, the depth knob.

What is checked, and against what:
- the supersampling resolve against a float64 reference written out here with explicit loops over the blocks and
  the IEC 61966-2-1 formulas (math.pow, no numpy helpers shared with the code): linear block means within 1e-12,
  8-bit results equal except where the reference lies within 1e-9 of a rounding tie (then within 1 step);
  a black/white checkerboard averages to linear 0.5 = sRGB 188, not to 128 (encoded averaging);
- the Pareto front on hand-made points whose front is worked out by hand in the test;
- a quick run on a 48x36 base with the msaa and ss knobs writes the CSV with exactly the documented columns,
  the markdown tables and the plot (with matplotlib); its ground-truth row has FLIP 0; 4x supersampling is
  strictly closer to the ground truth (FLIP and PSNR) than 1x, and the closest of the ss sweep; every row
  marked Pareto is non-dominated among the final-scene settings and every unmarked one is dominated;
- the depth knob on the depth-stress scene (two quads 0.05% apart at 1e4, near 0.01, far 1e5, far one drawn
  first) against its analytic image: reverse-Z depth32float has 0 wrong pixels and equals it exactly;
  standard depth24plus and depth32float have wrong pixels (lavapipe: all of them);
- the reverse-Z matrix the renderer applies stores depth 1 at near, 0 at far and the exact hyperbola between
  (against a perspective matrix and the depth formula written in the test).
No timing assertions: timings only have to be present and ordered (p10 <= median <= p90).
"""

from __future__ import annotations

import csv
import io
import math

import numpy as np
import pytest

from wgpurender.bench.accuracy_depth import analytic_image, write_depth_scene
from wgpurender.bench.accuracy_downsample import box_average, downsample_srgb8, linear_from_srgb8
from wgpurender.bench.accuracy_knobs import TOP, Settings, make_renderer
from wgpurender.bench.accuracy_pareto import dominates, pareto_front
from wgpurender.core.errors import UserError

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


# -- the resolve filter ------------------------------------------------------------------------------------------


def _decode(v8: int) -> float:
    c = v8 / 255.0
    return c / 12.92 if c <= 0.04045 else math.pow((c + 0.055) / 1.055, 2.4)


def _encode(lin: float) -> float:
    lin = min(max(lin, 0.0), 1.0)
    return 12.92 * lin if lin <= 0.0031308 else 1.055 * math.pow(lin, 1 / 2.4) - 0.055


def _reference(pixels: np.ndarray, k: int) -> np.ndarray:
    """Float64 linear RGB block means and alpha means, by explicit loops."""
    h, w = pixels.shape[0] // k, pixels.shape[1] // k
    out = np.zeros((h, w, 4))
    for y in range(h):
        for x in range(w):
            block = pixels[y * k:(y + 1) * k, x * k:(x + 1) * k].reshape(-1, 4)
            for ch in range(3):
                out[y, x, ch] = sum(_decode(int(v)) for v in block[:, ch]) / (k * k)
            out[y, x, 3] = sum(int(v) for v in block[:, 3]) / 255.0 / (k * k)
    return out


@pytest.mark.parametrize("k", [2, 3, 4])
def test_downsample_is_the_linear_light_area_average(k):
    rng = np.random.default_rng(k)
    pixels = rng.integers(0, 256, size=(3 * k, 5 * k, 4), dtype=np.uint8)
    ref = _reference(pixels, k)
    assert np.allclose(box_average(linear_from_srgb8(pixels), k), ref, rtol=0, atol=1e-12)
    got = downsample_srgb8(pixels, k).astype(int)
    exact = np.zeros_like(ref)
    for idx in np.ndindex(ref.shape[:2]):
        exact[idx][:3] = [_encode(v) * 255 for v in ref[idx][:3]]
        exact[idx][3] = ref[idx][3] * 255
    near_tie = np.abs(exact - np.floor(exact) - 0.5) < 1e-9
    want = np.floor(exact + 0.5).astype(int)
    assert np.array_equal(got[~near_tie], want[~near_tie])
    assert np.abs(got - want).max() <= 1


def test_downsample_averages_light_not_encoded_values():
    board = np.zeros((4, 4, 4), dtype=np.uint8)
    board[..., 3] = 255
    board[::2, ::2, :3] = 255
    board[1::2, 1::2, :3] = 255
    out = downsample_srgb8(board, 2)
    assert out.shape == (2, 2, 4)
    assert (out[..., :3] == 188).all() and (out[..., 3] == 255).all()  # sRGB(0.5) = 0.7354 -> 187.5 -> 188


def test_downsample_rejects_a_size_that_is_not_a_multiple():
    with pytest.raises(ValueError):
        downsample_srgb8(np.zeros((5, 6, 4), dtype=np.uint8), 2)
    img = np.arange(48, dtype=np.uint8).reshape(3, 4, 4)
    assert np.array_equal(downsample_srgb8(img, 1), img)


# -- the Pareto front ------------------------------------------------------------------------------------------


def test_pareto_front_on_hand_made_points():
    points = [(1, 5), (2, 3), (3, 3), (2, 4), (4, 1), (5, 1), (0.5, 9), (6, 0.5), (float("nan"), 0.0), (7, 0.5)]
    # (3,3) and (2,4) lose to (2,3); (5,1) to (4,1); (7,0.5) to (6,0.5); the NaN point takes no part.
    assert pareto_front(points) == [6, 0, 1, 4, 7]
    assert pareto_front([(1, 1), (1, 1), (2, 2)]) == [0, 1]  # equal points do not dominate each other
    assert pareto_front([]) == []
    assert dominates((1, 2), (1, 3)) and not dominates((1, 2), (1, 2)) and not dominates((1, 3), (2, 1))


# -- a quick run -----------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def quick_run(ctx, tmp_path_factory):
    from pathlib import Path

    from wgpurender.bench.accuracy_report import write_reports
    from wgpurender.bench.accuracy_run import AccuracyConfig, run_accuracy

    out = tmp_path_factory.mktemp("accuracy")
    config = AccuracyConfig(scene_path=Path("assets/scenes/final.toml"), base_size=(48, 36), frames=2, warmup=0,
                            rounds=2, knobs=("msaa", "ss"), out_dir=out, command="pytest")
    run = run_accuracy(config, ctx, progress_stream=io.StringIO())
    return run, write_reports(run, out)


def test_quick_run_writes_csv_markdown_and_plot(quick_run):
    from wgpurender.bench.accuracy_report import CSV_COLUMNS, PLOT_NAME
    from wgpurender.bench.report import have_matplotlib

    run, paths = quick_run
    with paths["csv"].open() as f:
        rows = list(csv.DictReader(f))
    with paths["csv"].open() as f:
        assert tuple(next(csv.reader(f))) == CSV_COLUMNS
    assert len(rows) == len(run.rows)
    assert {r["sweep"] for r in rows} >= {"ground truth", "msaa", "ss", "msaa1 x ss", "lowest"}
    for r in rows:
        assert float(r["wall_ms_p10"]) <= float(r["wall_ms_median"]) <= float(r["wall_ms_p90"])
    text = paths["markdown"].read_text()
    assert "## Final scene" in text and "| sweep | level |" in text and "Pareto front" in text
    if have_matplotlib():
        assert paths["plot"].name == PLOT_NAME and paths["plot"].read_bytes()[:8] == PNG_MAGIC
        assert f"]({PLOT_NAME})" in text
    else:
        assert "Plot skipped" in text


def test_ground_truth_equivalent_setting_has_the_smallest_error(quick_run):
    run, _ = quick_run
    gt = next(r for r in run.rows if r.case.sweep == "ground truth")
    assert gt.flip == 0.0 and math.isinf(gt.psnr)
    ss = {r.case.settings.ss: r for r in run.rows if r.case.sweep == "ss"}
    assert ss[4].flip < ss[1].flip and ss[4].psnr > ss[1].psnr
    assert min(ss.values(), key=lambda r: r.flip) is ss[4]
    assert all(r.m.pixels.shape == (36, 48, 4) for r in run.rows)


def test_pareto_marks_match_domination(quick_run):
    run, _ = quick_run
    final = {r.case.key: r for r in run.rows if r.case.sweep != "ground truth"}.values()
    for r in final:
        beaten = any(dominates((o.time_ms, o.flip), (r.time_ms, r.flip)) for o in final if o is not r)
        assert r.pareto == (not beaten), r.case


def test_cli_lists_accuracy():
    from wgpurender.bench import accuracy
    from wgpurender.cli import build_parser

    args = build_parser().parse_args(["bench", "accuracy", "--quick", "--knob", "ss", "--out", "x"])
    assert args.func is accuracy.run and args.knobs == ["ss"] and args.quick


# -- the depth knob ------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def depth_scene(tmp_path_factory):
    from wgpurender.core.scene import load_scene

    return load_scene(write_depth_scene(tmp_path_factory.mktemp("depth"), (64, 48)))


def _render(ctx, scene, settings, size=(64, 48), knobs=("depth",)):
    from wgpurender.wgpu_path.scene import render_frame

    renderer = make_renderer(ctx, scene, settings, size, knobs=knobs)
    target = renderer.create_output()
    return render_frame(ctx, renderer, target)[0], renderer


def test_reverse_z_depth32float_resolves_the_depth_stress_scene(ctx, depth_scene):
    from numerics.depth_planes import wrong_pixels

    image, renderer = _render(ctx, depth_scene, TOP.with_(depth="reverse-z"))
    assert renderer.plan.attachment("depth").format == "depth32float" and renderer.scene_pass.reverse_z
    assert wrong_pixels(image) == 0
    assert np.array_equal(image, analytic_image((64, 48)))


@pytest.mark.parametrize("level", ["depth24plus", "depth32float"])
def test_standard_depth_z_fights_in_the_depth_stress_scene(ctx, depth_scene, level):
    from numerics.depth_planes import wrong_pixels

    image, renderer = _render(ctx, depth_scene, TOP.with_(depth=level))
    assert renderer.plan.attachment("depth").format == level and not renderer.scene_pass.reverse_z
    assert wrong_pixels(image) > 0


def test_reverse_z_matrix_is_the_reverse_z_perspective():
    """REVERSE_Z applied to a right-handed 0..1 perspective (written out here) stores depth 1 at the near plane,
    0 at the far plane, and the exact hyperbola near * (far - d) / (d * (far - near)) between them."""
    from wgpurender.core.course.shading import REVERSE_Z

    for near, far in ((0.1, 50.0), (0.01, 1e5)):
        f = 1.0 / math.tan(math.radians(42.0) / 2.0)
        standard = np.array([[f / (4 / 3), 0, 0, 0], [0, f, 0, 0],
                             [0, 0, far / (near - far), far * near / (near - far)], [0, 0, -1, 0]])
        m = np.asarray(REVERSE_Z, np.float64) @ standard
        for d in (near, 2 * near, 1.0, far / 3, far):
            clip = m @ np.array([0.0, 0.0, -d, 1.0])
            assert clip[2] / clip[3] == pytest.approx(near * (far - d) / (d * (far - near)), rel=1e-9, abs=1e-12)


def test_knobs_reach_the_plan_and_bad_combinations_are_user_errors(ctx, depth_scene):
    from wgpurender.core.scene import load_scene

    scene = load_scene("assets/scenes/final.toml")
    s = Settings(msaa=1, format="rgba32float", filter="nearest", depth="depth24plus")
    renderer = make_renderer(ctx, scene, s, (32, 24))
    plan = renderer.plan
    assert plan.attachment("scene_color").format == "rgba32float" and plan.attachment("depth").format == "depth24plus"
    assert all(p.color_format == "rgba32float" and p.depth_format == "depth24plus" for p in plan.pipelines)
    assert all(d.sampler.min_filter == "nearest" and d.sampler.lod_max_clamp == 0.0 for d in plan.scene_pass.draws)
    assert not any(t.mipmaps for t in plan.textures)
    with pytest.raises(UserError, match="cannot be multisampled"):
        make_renderer(ctx, scene, s.with_(msaa=4), (32, 24))
    with pytest.raises(UserError, match="post chain"):
        make_renderer(ctx, depth_scene, TOP, (32, 24), knobs=("format",))
