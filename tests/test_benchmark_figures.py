"""docs/benchmarks.md's generated figures are those of the committed run outputs (wgpurender/bench/figures.py)."""

from __future__ import annotations

from wgpurender.bench import figures


def test_issue31_figures_are_generated_from_the_committed_runs():
    text = figures.DOC.read_text()
    block = text[text.index(figures.BEGIN): text.index(figures.END) + len(figures.END)]
    assert block == figures.section(), "regenerate: python -m wgpurender.bench.figures"


def test_every_run_named_has_its_csv_and_report():
    for _, folder, csv, _ in figures.RUNS:
        base = figures.REPO / "docs" / folder
        assert (base / csv).is_file()
        report = (base / csv).parent / "report.md"
        assert report.is_file() and "command" in report.read_text()


def test_perf2_roofline_rows_read_back_what_post_roofline_wrote(tmp_path):
    """The roofline CSV's variant holds a comma, unquoted: the reader must still line up every column."""
    from wgpurender.bench import figures_post
    from wgpurender.bench.post_roofline import PassTime, csv_text

    rows = [PassTime("compute, fused", "tonemap", "compute", 8_000_000, 0.5, 0.25),
            PassTime("compute, fused", "fxaa+vignette", "compute", 4_000_000, 0.25, 0.125, 2_000_000),
            PassTime("compute, unfused", "tonemap", "compute", 8_000_000, 9.0, 1.0)]
    path = tmp_path / "r.csv"
    path.write_text(csv_text(rows))
    read = figures_post.roofline_rows(path)
    assert [(r["variant"], r["effects"], r["path"], r["bytes_moved"], r["copy_bytes"]) for r in read] == [
        ("compute, fused", "tonemap", "compute", 8e6, 0), ("compute, fused", "fxaa+vignette", "compute", 4e6, 2e6),
        ("compute, unfused", "tonemap", "compute", 8e6, 0)]
    assert figures_post.chain_ratio(read) == (0.75, 0.375, 2)
    # a run with the knob post_intermediate: its column is read apart, and only auto rows make the fused chain
    rows.append(PassTime("compute, fused, rgba8unorm", "tonemap", "compute", 6_000_000, 0.4, 0.2,
                         intermediate="rgba8unorm"))
    path.write_text(csv_text(rows))
    read = figures_post.roofline_rows(path)
    assert [(r["variant"], r["intermediate"], r["bytes_moved"]) for r in read][2:] == [
        ("compute, unfused", "auto", 8e6), ("compute, fused, rgba8unorm", "rgba8unorm", 6e6)]
    assert figures_post.chain_ratio(read) == (0.75, 0.375, 2)


def test_perf2_run_has_its_files_and_consistent_roofline_columns():
    from wgpurender.bench import figures_post

    base = figures.REPO / "docs" / figures_post.RUN
    for name in ("machine.txt", "commands.txt", "scene/report.md", "dawn/report.md", "native/report.md"):
        assert (base / name).is_file(), name
    for scene in figures_post.ROOFLINE_SCENES:
        rows = figures_post.roofline_rows(base / "roofline" / f"post-roofline-{scene}.csv")
        assert {r["variant"] for r in rows} >= {"compute, fused", "fragment, fused"}
        for r in rows:  # GB/s is bytes / time: the columns are where the reader put them
            assert abs(r["gbps"] - r["bytes_moved"] / (r["ms"] * 1e6)) <= 0.01 * r["gbps"]


def test_roofline_csv_is_a_csv_a_reader_splits_right():
    """A variant with a comma is quoted: csv.DictReader gives every column its own value."""
    import csv
    import io

    from wgpurender.bench.post_roofline import PassTime, csv_text

    text = csv_text([PassTime("compute, fused", "fxaa+vignette", "compute", 4_000_000, 0.25, 0.125, 2_000_000)])
    [row] = list(csv.DictReader(io.StringIO(text)))
    assert (row["variant"], row["effects"], row["bytes_moved"], row["ms"], row["copy_bytes"]) == (
        "compute, fused", "fxaa+vignette", "4000000", "0.25", "2000000")
