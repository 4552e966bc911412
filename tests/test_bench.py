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
        if r.metric != "readback_ms" and "difference" not in r.case:  # differences may be negative
            assert 0.0 <= r.p10 <= r.median + 1e-3 and r.median <= r.p90 + 1e-3, r


def test_every_common_stage_measured_on_both_paths(quick_run):
    from wgpurender.bench.frames import common_stages

    run, _, _ = quick_run
    measured = {(r.case, r.path) for r in run.results if r.family == "frames" and r.metric == "frame_ms"}
    for stage in common_stages():
        assert (stage, "wgpu") in measured and (stage, "raw") in measured, stage


def test_final_scene_measured_on_both_paths(quick_run):
    """The raw path draws final.toml (FXAA in a render pass of its own, issue 16) and final_subpass.toml, so the
    report has both pairs and no note of a missing raw peer."""
    run, _, _ = quick_run
    measured = {(r.case, r.path) for r in run.results if r.family == "scene" and r.metric == "frame_ms"}
    assert {("final_subpass", "wgpu"), ("final_subpass", "raw"), ("final", "wgpu"), ("final", "raw")} <= measured
    assert not any("no raw peer" in n for n in run.notes), run.notes
    report = (quick_run[2] / "report.md").read_text()
    assert ".toml) wgpu / raw frame time <= 1.10" in report


def test_families_produce_their_rows(quick_run):
    run, _, _ = quick_run
    families = {r.family for r in run.results}
    assert {"frames", "post-effects", "post-probe", "msaa-post", "objects"} <= families
    modes = {r.case.split("/")[0] for r in run.results if r.family == "objects"}
    expected = set(MODES) if run_ctx_has_immediates(run) else set(MODES) - {"immediates"}
    assert modes == expected


def run_ctx_has_immediates(run) -> bool:
    from wgpurender.gpu import get_context

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

    from wgpurender.bench.startup import PHASES, run_child

    result = run_child("raw", "triangle", (64, 48), dict(os.environ, WGPURENDER_VALIDATION="0"))
    assert set(result) == set(PHASES)
    assert all(v >= 0.0 for v in result.values())
    assert result["total_ms"] >= result["first_frame_ms"]


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


def test_cli_lists_perf_and_rejects_unknown_family(capsys):
    from wgpurender.cli import build_parser, main

    args = build_parser().parse_args(["bench", "perf", "--quick", "--out", "x"])
    assert args.suite == "perf" and args.quick
    assert main(["bench", "perf", "--only", "nonsense", "--out", "unused"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "unknown benchmark family 'nonsense'" in err
