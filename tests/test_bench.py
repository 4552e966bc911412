"""The benchmark harness (wgpurender/bench): it runs, and what it writes has the promised structure.

No timing assertions: numbers from a shared CPU machine prove nothing. What is checked:
the CSV has exactly the documented columns and every row a sane spread (p10 <= median <= p90);
every stage both paths render has wgpu and raw rows; the markdown report has its sections
and tables; plots are PNG files (when matplotlib is installed); the CLI lists ``perf`` and
refuses unknown families in one line. The many-objects renderer draws the same image in all
four modes, and that image matches quads rasterised in numpy (pixel centres inside each
rectangle, later objects on top) with at most 0.5% of pixels off (edge-rule ties).
"""

from __future__ import annotations

import csv
import time

import numpy as np
import pytest

from wgpurender.bench.objects import MODES, ObjectsRenderer, object_data
from wgpurender.bench.perf import PerfConfig, run_perf, write_reports
from wgpurender.bench.report import CSV_COLUMNS, have_matplotlib, read_csv

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def quick_run(ctx, tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    config = PerfConfig(quick=True, out_dir=out, families=("frames", "post", "msaa-post", "objects", "scene"), frames=2,
                        command="pytest")
    run = run_perf(config, ctx, log=lambda _: None)
    return run, write_reports(run, out), out


def test_csv_has_documented_columns_and_sane_rows(quick_run):
    run, paths, _ = quick_run
    with paths["csv"].open() as f:
        assert tuple(next(csv.reader(f))) == CSV_COLUMNS
    rows = read_csv(paths["csv"])
    assert len(rows) == len(run.results) > 0
    for r in rows:
        assert r.n >= 1 and np.isfinite(r.median)
        if "difference" not in r.case:  # readback_ms too: paired frames, never negative; msaa-post differences may be
            assert 0.0 <= r.p10 <= r.median + 1e-3 and r.median <= r.p90 + 1e-3, r
            assert np.isnan(r.p99) or r.p90 <= r.p99 + 1e-3, r


def test_tails_are_reported_beside_the_median():
    """p99 catches a stall in 5 of 100 frames; p90 > 3x the median flags the case in the report."""
    from wgpurender.bench.markdown import _tails
    from wgpurender.bench.report import Result
    from wgpurender.wgpu_path.device.timing import Stats

    rare = Stats.of([1.0] * 95 + [20.0] * 5)
    assert (rare.median, rare.p90, rare.p99) == (1.0, 1.0, 20.0)
    often = Result.of("frames", "triangle", "wgpu", "800x600", "frame_ms", Stats.of([1.0] * 80 + [10.0] * 20))
    calm = Result.of("frames", "triangle", "raw", "800x600", "frame_ms", rare)
    assert often.has_tail() and not calm.has_tail()
    text = _tails([often, calm])
    assert text.startswith("1 of 2 timed rows") and "| frames | triangle | wgpu |" in text and "p99 10.0" in text


def test_every_common_stage_measured_on_both_paths(quick_run):
    from wgpurender.bench.frames import common_stages

    run, _, _ = quick_run
    measured = {(r.case, r.path) for r in run.results if r.family == "frames" and r.metric == "frame_ms"}
    for stage in common_stages():
        assert (stage, "wgpu") in measured and (stage, "raw") in measured, stage


def test_quick_run_judges_no_target(quick_run):
    """--quick measures tiny sizes with few frames: its Targets table gives no met / not met verdict."""
    _, paths, _ = quick_run
    text = paths["markdown"].read_text()
    table = text.split("## Targets", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in table.splitlines() if line.startswith("| ") and not line.startswith(("| target", "| ---"))]
    assert rows, table
    for row in rows:
        status = row.rstrip(" |").rsplit("|", 1)[-1].strip()
        assert status.startswith("not judged") or status == "n/a", row


def _fake_run(adapter: str, wgpu_ms: float, raw_ms: float):
    from types import SimpleNamespace

    from wgpurender.bench.report import Result

    results = [Result("frames", "3d", path, "800x600", "frame_ms", ms, ms, ms, 5, "")
               for path, ms in (("wgpu", wgpu_ms), ("raw", raw_ms))]
    results.append(Result("scene", "vulkan_tutorial_28", "wgpu", "800x600", "frame_ms", 40.0, 40.0, 40.0, 5, ""))
    return SimpleNamespace(config=PerfConfig(quick=False), machine={"adapter": adapter}, results=results)


@pytest.mark.parametrize(("adapter", "wgpu_ms", "raw_ms", "frames_status"), [
    ("NVIDIA H200 (Vulkan, DiscreteGPU, 570)", 1.04, 1.0, "met"),          # 1.04 <= 1.05 on a GPU (issue 22)
    ("NVIDIA H200 (Vulkan, DiscreteGPU, 570)", 1.08, 1.0, "not met"),
    ("llvmpipe (Vulkan, CPU, Mesa 22.3.6)", 1.08, 1.0, "not met"),         # 1.08 > 1.05 on lavapipe
    ("llvmpipe (Vulkan, CPU, Mesa 22.3.6)", 1.04, 1.0, "met"),
])
def test_targets_judge_only_where_they_apply(adapter, wgpu_ms, raw_ms, frames_status):
    """Frame-time ratio: 1.05 on a GPU and on lavapipe; the C++ tutorial's lavapipe numbers judge lavapipe only."""
    from wgpurender.bench.markdown import _targets

    rows = {line.split("|")[1].strip(): line.split("|")[-2].strip()
            for line in _targets(_fake_run(adapter, wgpu_ms, raw_ms)).splitlines()[2:]}
    frames = next(v for k, v in rows.items() if k.startswith("wgpu / raw frame time"))
    assert frames == frames_status
    tutorial = rows["tutorial chapter 28 (47 ms given, C++ not built here) within 1.05x"]
    if "CPU" in adapter:
        assert tutorial == "met"  # 40 ms <= 1.05 * 47 ms
    else:
        assert tutorial.startswith("not judged")


def test_readback_from_pairs_is_never_negative():
    """Pairs whose differences have a negative median (readback lost in noise) report 0, and say so."""
    from wgpurender.bench.frames import readback_result

    r = readback_result("frames", "x", "wgpu", "8x8", [-0.3, -0.1, 0.05])
    assert r.median == 0.0 and r.p10 == 0.0 and "below the noise" in r.note
    r = readback_result("frames", "x", "wgpu", "8x8", [0.1, 0.2, 0.3])
    assert r.median == pytest.approx(0.2)


def test_final_scene_measured_on_both_paths(quick_run):
    """The raw path draws final.toml (FXAA in a render pass of its own, issue 16) and final_subpass.toml, so the
    report has both pairs and no note of a missing raw peer."""
    run, _, _ = quick_run
    measured = {(r.case, r.path) for r in run.results if r.family == "scene" and r.metric == "frame_ms"}
    assert {("final_subpass", "wgpu"), ("final_subpass", "raw"), ("final", "wgpu"), ("final", "raw")} <= measured
    assert not any("no raw peer" in n for n in run.notes), run.notes
    report = (quick_run[2] / "report.md").read_text()
    for case in ("final", "final_subpass"):
        assert f"final scene ({case}.toml) wgpu / raw frame time <= " in report
    calls = {r.case: r for r in run.results if r.family == "scene" and r.metric == "native_calls"}
    untimed = {r.case for r in run.results if r.family == "scene" and r.metric == "cpu_ms:untimed"}
    assert {"final", "final_subpass"} <= set(calls) and {"final", "final_subpass"} <= untimed
    assert "native calls per frame" in report and "queue.submit 1" in calls["final"].note


def test_families_produce_their_rows(quick_run):
    run, _, _ = quick_run
    families = {r.family for r in run.results}
    assert {"frames", "post-effects", "post-probe", "msaa-post", "objects"} <= families
    modes = {r.case.split("/")[0] for r in run.results if r.family == "objects"}
    expected = set(MODES) if run_ctx_has_immediates(run) else set(MODES) - {"immediates"}
    assert modes == expected | {"gpu-animated", "gpu-compute-raster"}
    untimed = {r.case.split("/")[0] for r in run.results if r.family == "objects" and r.metric == "cpu_ms:untimed"}
    assert untimed == {"gpu-animated", "gpu-compute-raster"}


def run_ctx_has_immediates(run) -> bool:
    from wgpurender.wgpu_path.device.context import get_context

    return get_context("Vulkan").has("immediates")


def test_markdown_report_has_sections_and_tables(quick_run):
    _, paths, _ = quick_run
    text = paths["markdown"].read_text()
    for heading in ("## Targets", "## Frame time", "## Post effects", "## Many objects", "### frame_ms"):
        assert heading in text, heading
    assert "| case | size | metric | wgpu ms | raw ms | wgpu/raw |" in text
    assert "| mode | objects | frame ms | CPU ms | GPU ms | fps | set-up ms |" in text


def test_plots_are_png_files(quick_run):
    _, paths, out = quick_run
    if not have_matplotlib():
        pytest.skip("matplotlib not installed: plots are optional")
    plots = [p for k, p in paths.items() if k.startswith("plot_")]
    assert {p.name for p in plots} >= {"perf_frames.png", "perf_objects.png", "perf_post.png"}
    for p in plots:
        assert p.read_bytes()[:8] == PNG_MAGIC


def test_startup_child_reports_every_phase():
    import os

    from wgpurender.bench.startup import METRICS, run_child

    before = time.perf_counter()
    result = run_child("raw", "triangle", (64, 48), dict(os.environ, WGPURENDER_VALIDATION="0"))
    wall = (time.perf_counter() - before) * 1e3  # the parent's view of the whole child
    assert set(result) == set(METRICS)
    assert result["spawn_ms"] <= wall
    assert all(v >= 0.0 for v in result.values())
    parts = sum(result[p] for p in ("import_ms", "context_ms", "setup_ms", "first_frame_ms"))
    assert result["total_ms"] == pytest.approx(parts)  # the phases add up to the first pixel
    assert result["spawn_ms"] > result["total_ms"]  # the interpreter's start-up comes before the child's clock


def _numpy_quads(data: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Rasterise the quads: a pixel is covered when its centre lies inside the NDC rectangle (y up)."""
    w, h = size
    img = np.zeros((h, w, 4), dtype=np.float64)
    img[..., 3] = 1.0
    x = (np.arange(w) + 0.5) / w * 2.0 - 1.0
    y = 1.0 - (np.arange(h) + 0.5) / h * 2.0
    for cx, cy, hw, hh, r, g, b, a in data.astype(np.float64):
        cols = (x > cx - hw) & (x < cx + hw)
        rows = (y > cy - hh) & (y < cy + hh)
        img[np.ix_(rows, cols)] = (r, g, b, a)
    return np.round(img * 255.0)


def test_objects_modes_draw_the_numpy_image(ctx):
    size, count = (200, 150), 60
    half = (0.05, 0.07)
    reference = _numpy_quads(object_data(count, 0.0, half_size=half), size)
    images = {}
    for mode in MODES:
        if mode == "immediates" and not ctx.has("immediates"):
            continue
        images[mode] = ObjectsRenderer(ctx, mode, count, size, half).pixels().astype(np.float64)
    first = next(iter(images.values()))
    for mode, img in images.items():
        assert np.array_equal(img, first), f"{mode} differs from {next(iter(images))}"
        off = np.any(np.abs(img - reference) > 1.0, axis=-1).mean()
        assert off <= 0.005, f"{mode}: {off:.4%} of pixels differ from the numpy quads"
    assert (np.abs(first[..., :3]).sum(axis=-1) > 0).mean() > 0.1  # the quads cover a good part of the image


@pytest.mark.parametrize("mode", ["gpu-animated", "gpu-compute-raster"])
def test_gpu_animated_objects_draw_the_numpy_image(ctx, mode):
    """Animation on the GPU, the same drift formula: the numpy quads of object_data at t, later ones on top, drawn
    by the raster pipeline (indirect draw) or by the compute rasteriser (twice: its pixel indices reset per frame)."""
    from wgpurender.bench.objects_gpu import GpuAnimatedRenderer

    size, count, half, t = (200, 150), 60, (0.05, 0.07), 1.3
    renderer = GpuAnimatedRenderer(ctx, count, size, half, mode=mode)
    renderer.t = t
    img = renderer.pixels().astype(np.float64)
    reference = _numpy_quads(object_data(count, t, half_size=half), size)
    off = np.any(np.abs(img - reference) > 1.0, axis=-1).mean()
    assert off <= 0.005, f"{off:.4%} of pixels differ from the numpy quads"
    assert np.array_equal(renderer.pixels(), img)  # the next frame, same t: the same image
    if mode == "gpu-animated":
        assert renderer.visible_count() == count  # every quad is inside the view


def test_gpu_culling_counts_the_objects_in_view(ctx):
    """Zoomed 2x about (0.3, -0.2): the indirect draw's instance count is the number of quads overlapping the view
    box, counted here in numpy from the same formula (a quad within 1e-4 of the box edge may go either way)."""
    from wgpurender.bench.objects_gpu import GpuAnimatedRenderer

    count, half, (ox, oy, zoom), t = 5000, (0.01, 0.01), (0.3, -0.2, 2.0), 0.7
    renderer = GpuAnimatedRenderer(ctx, count, (64, 48), half, view=(ox, oy, zoom))
    renderer.t = t
    renderer.frame()
    data = object_data(count, t, half_size=half).astype(np.float64)
    gap = np.maximum(np.abs((data[:, 0] - ox) * zoom) - half[0] * zoom,
                     np.abs((data[:, 1] - oy) * zoom) - half[1] * zoom)
    sure, edge = int((gap < 1.0 - 1e-4).sum()), int((np.abs(gap - 1.0) <= 1e-4).sum())
    got = renderer.visible_count()
    assert sure <= got <= sure + edge and 0 < got < count // 2


def test_gpu_animated_frame_writes_one_small_uniform(ctx):
    """Whatever the count, a frame's CPU work is the same few calls: one 32-byte write, no per-object data."""
    from wgpurender.bench.calls import count_frame
    from wgpurender.bench.objects_gpu import GpuAnimatedRenderer

    for count in (100, 20_000):
        renderer = GpuAnimatedRenderer(ctx, count, (64, 48))
        written: list[int] = []
        real = ctx.queue.write_buffer

        def spy(buffer, offset, data, *rest, _real=real, _written=written):
            _written.append(len(bytes(data)))
            return _real(buffer, offset, data, *rest)

        ctx.queue.write_buffer = spy
        try:
            calls = count_frame(ctx, renderer.record, renderer.target)
        finally:
            del ctx.queue.write_buffer
        assert written == [32] and sum(calls.values()) == 15, dict(calls)


def test_cli_lists_perf_and_rejects_unknown_family(capsys):
    from wgpurender.cli import build_parser, main

    args = build_parser().parse_args(["bench", "perf", "--quick", "--out", "x"])
    assert args.suite == "perf" and args.quick
    assert main(["bench", "perf", "--only", "nonsense", "--out", "unused"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "unknown benchmark family 'nonsense'" in err


def test_stage_a_binding_cannot_draw_is_a_not_offered_row(ctx, monkeypatch, tmp_path):
    """Dawn has no 'clear-texture' (issue 31, its H100 run stopped there): bench perf goes on past the stage
    and says so in one line and one CSV row, the other stages still measured."""
    import dataclasses

    import wgpurender.bench.frames as frames
    from wgpurender.bench.perf import PerfRun as Run
    from wgpurender.bench.perf import _frames

    no_clear = dataclasses.replace(ctx, features=ctx.features - {"clear-texture"})
    monkeypatch.setattr(frames, "common_stages", lambda: ["clear", "clear-pass"])
    config = PerfConfig(quick=True, raw=False, families=("frames",), frames=2)
    run, lines = Run(config, {}), []
    _frames(no_clear, config, run, lines.append)
    skipped = [r for r in run.results if r.metric == "not offered"]
    assert [(r.case, r.path, r.size, r.n) for r in skipped] == [("clear", "wgpu", "96x64", 0)]
    assert "clear-texture" in skipped[0].note
    assert [line for line in lines if "not offered" in line] == [
        f"  frames: clear 96x64 not offered by this binding: {skipped[0].note}"]
    assert {r.case for r in run.results if r.metric == "frame_ms"} == {"clear-pass"}
    assert any("not offered" in n and "clear (" in n for n in run.notes)
    write_reports(run, tmp_path)
    rows = [r for r in read_csv(tmp_path / "results.csv") if r.case == "clear"]
    assert [(r.metric, r.n) for r in rows] == [("not offered", 0)]
