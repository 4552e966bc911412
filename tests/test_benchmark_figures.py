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
