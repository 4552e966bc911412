"""docs/accuracy.md's teaching section quotes the committed run in docs/accuracy-teaching/, figure for figure.

Every table row of the section ("What each knob is for") is looked up in the run's CSV files by its case and
setting, and each number must be the CSV's value rounded to the digits the doc prints. The run records its
machine, date and command; the section's explanations are the words the report prints
(wgpurender/bench/accuracy_teaching.py), and the notebook's MSAA chart is named where it is explained.
"""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import pytest

from wgpurender.bench.accuracy_teaching import TEXTS

REPO = Path(__file__).resolve().parent.parent
DOC = REPO / "docs" / "accuracy.md"
RUN = REPO / "docs" / "accuracy-teaching"
START, END = "## What each knob is for: the teaching cases", "## Analytic ground truth"


def _section() -> str:
    text = DOC.read_text()
    return text[text.index(START):text.index(END)]


def _flat(text: str) -> str:
    return " ".join(text.split())


def _rows(text: str) -> list[list[str]]:
    rows = [[c.strip() for c in line.strip().strip("|").split("|")] for line in text.splitlines()
            if line.startswith("| ") and not line.startswith("| case") and not line.startswith("| knob")]
    return rows


def _csv(name: str) -> list[dict]:
    with (RUN / name).open() as f:
        return list(csv.DictReader(f))


def _same(doc: str, value: str) -> bool:
    """The doc's figure is the CSV's value rounded to the doc's digits."""
    digits = len(doc.partition(".")[2])
    return f"{float(value):.{digits}f}" == doc


def test_the_run_records_machine_date_and_command():
    machine = (RUN / "machine.txt").read_text()
    for key in ("machine:", "adapter:", "date: 2026-", "command: wgpurender bench accuracy --truth analytic"):
        assert key in machine
    md = (RUN / "accuracy_analytic.md").read_text()
    assert "- command: `wgpurender bench accuracy --truth analytic --quick" in md
    date = re.search(r"- date: (\S+ \S+) UTC", md).group(1)
    assert date in machine and date in _section()


def test_every_figure_of_the_section_is_the_runs():
    shimmer = {(r["section"], r["setting"]): r for r in _csv("accuracy_shimmer.csv")}
    analytic = {(r["section"], r["setting"]): r for r in _csv("accuracy_analytic.csv")}
    rows = _rows(_section())
    assert len(rows) == len(shimmer) + 6  # every shimmer row, and the HDR and shading-precision rows
    for row in rows:
        key = (row[0], row[1])
        if key in shimmer:
            expected = [shimmer[key][c] for c in ("shimmer", "still_error", "truth_change")]
        else:
            expected = [analytic[key][c] for c in ("flip_mean", "psnr_db", "linear_mae")]
        assert all(_same(d, v) for d, v in zip(row[2:], expected, strict=True)), (row, expected)


def test_the_doc_states_the_orderings_the_run_shows():
    s = {r["setting"]: float(r["shimmer"]) for r in _csv("accuracy_shimmer.csv") if r["section"] == "minified plane"}
    e = {r["setting"]: float(r["shimmer"]) for r in _csv("accuracy_shimmer.csv") if r["section"] == "edges"}
    assert s["trilinear"] < min(s["nearest"], s["linear"]) and e["msaa4"] < 0.5 * e["none"]


@pytest.mark.parametrize("name", sorted(TEXTS))
def test_the_section_carries_the_reports_words(name):
    assert _flat(TEXTS[name]) in _flat(_section())


def test_the_notebook_chart_is_the_case_the_explanation_names():
    """The explanation says the notebook's triangle is where MSAA 4x lowers the error: the notebook measures MSAA on
    the triangle (tests/test_notebook.py asserts MSAA 4x below MSAA 1) and points at the final-scene explanation."""
    cells = json.loads((REPO / "examples" / "course_tour.ipynb").read_text())["cells"]
    text = ["".join(c["source"]) for c in cells]
    chart = next(t for t in text if "for msaa in (1, 4)" in t)
    assert "w.render('triangle'" in chart
    words = next(t for t in text if t.startswith("## 4. Accuracy"))
    assert "docs/accuracy.md" in words and "few edges" in words
    assert "examples/course_tour.ipynb, section 4" in TEXTS["still frame"]
