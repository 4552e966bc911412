"""wgpurender verify (wgpurender/verify.py): the matrix's files, its exit status, and its skips.

A --quick run (stages triangle and 3d, scene unlit) on this adapter: the wgpu and raw renders are
identical, and the raw renders are within the table's bounds of the committed references (as
tests/test_vulkan_ref.py checks too). A real change (the committed triangle shifted by one pixel,
handed to verify in place of the file) must turn its row into FAIL, write a heatmap, and exit 1.
"""

from __future__ import annotations

import csv
import re

import numpy as np

from wgpurender import verify
from wgpurender.cli import main
from wgpurender.core.files.imageio import load_png
from wgpurender.core.verdict.tolerances import load_table


def _rows(out) -> list[dict]:
    with open(out / "verify.csv", newline="") as f:
        return list(csv.DictReader(f))


def test_quick_matrix_passes_and_writes_its_files(tmp_path, capsys):
    out = tmp_path / "verify"
    assert main(["verify", "--quick", "--out", str(out)]) == 0, capsys.readouterr().out
    rows = {(r["name"], r["comparison"]): r for r in _rows(out)}
    assert set(rows) == {("triangle", "wgpu vs raw"), ("triangle", "raw vs committed"), ("3d", "wgpu vs raw"),
                         ("3d", "raw vs committed"), ("unlit", "wgpu vs raw"), ("unlit", "raw vs committed")}
    for (_, comparison), row in rows.items():
        expected = "identical" if comparison == "wgpu vs raw" else ("identical", "pass")
        assert row["status"] in expected, row
        assert row["device"] and float(row["flip_mean"]) >= 0
    assert "| triangle | raw vs committed |" in (out / "verify.md").read_text()
    for row in rows.values():  # a heatmap for every comparison that is not identical, and only those
        assert bool(row["heatmap"]) == (row["status"] != "identical")
        assert not row["heatmap"] or load_png(out / row["heatmap"]).shape[:2] == (192, 256)
    recalibrated = load_table(out / "tolerances.toml")
    cls = verify.driver_class(rows[("triangle", "wgpu vs raw")]["device"])
    assert "CPU" in recalibrated["references"]["triangle"][cls]["measured"]


def test_a_real_change_fails_the_matrix(tmp_path, monkeypatch, capsys):
    """The committed triangle, shifted one pixel to the right, read by verify: FAIL, a heatmap, exit status 1."""
    real_load = verify.load_png

    def shifted(path):
        image = real_load(path)
        return np.roll(image, 1, axis=1) if path.name == "triangle.png" else image

    monkeypatch.setattr(verify, "load_png", shifted)
    out = tmp_path / "verify"
    assert main(["verify", "--quick", "--out", str(out)]) == 1
    last = capsys.readouterr().out.splitlines()[-1]
    failed = [r for r in _rows(out) if r["status"] == "FAIL"]
    skipped = sum(r["status"] == "skipped" for r in _rows(out))
    assert last == f"verify: FAIL: {len(_rows(out)) - 1 - skipped} passed, 1 over their bound, {skipped} skipped"
    assert [(r["name"], r["comparison"]) for r in failed] == [("triangle", "raw vs committed")]
    # whichever bound this driver class's row trips first (lavapipe: max diff; a GPU: changed pixels or FLIP)
    assert re.search(r"(max diff|changed pixels|FLIP mean) \S+ > \S+", failed[0]["note"]), failed[0]["note"]
    assert (out / failed[0]["heatmap"]).is_file()


def test_scenes_that_need_the_anchors_are_skipped_with_the_reason(tmp_path, monkeypatch):
    monkeypatch.setattr(verify, "ANCHORS", tmp_path / "no-anchors")
    monkeypatch.setattr(verify, "QUICK", {"stages": (), "scenes": ("vulkan_tutorial_28",)})
    report = verify.run_verify(tmp_path / "out", quick=True)
    assert [(r.status, r.name) for r in report.rows] == [("skipped", "vulkan_tutorial_28")]
    assert "no-anchors" in report.rows[0].note and "absent" in report.rows[0].note


def test_an_output_path_that_is_a_file_is_a_user_error(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("")
    assert main(["verify", "--quick", "--out", str(blocker)]) == 2
    assert "is not a folder" in capsys.readouterr().err


def test_recalibration_fills_provisional_rows_and_only_widens_measured_ones():
    """One GPU run replaces the provisional gpu rows (and the class's provenance); on a measured class the
    bounds never shrink, and the new measurement is appended to the row's provenance."""
    from wgpurender.core.verdict.tolerances import Metrics

    table = load_table()
    # the state before any GPU run, whatever GPU calibrated the committed table since
    table["classes"]["gpu"] = {"bounded_by": "PROVISIONAL: guesses", "provisional": True}
    table["references"]["triangle"]["gpu"] = {"max_abs": 255, "changed": 0.1, "flip_mean": 0.01,
                                              "measured": "not yet", "provisional": True}
    wide = Metrics(40, 0.2, 9830, 0.02, 49152)
    rows = [verify.Row("stage", "triangle", "raw vs committed", "pass", wide, reference="triangle"),
            verify.Row("stage", "triangle", "wgpu vs raw", "identical", Metrics(0, 0.0, 0, 0.0, 49152))]
    gpu = verify.recalibrated(table, verify.Report("Test GPU X (1.0)", "Xeon", "gpu", "2026-11-23", rows))
    row = gpu["references"]["triangle"]["gpu"]
    assert (row["max_abs"], row["changed"], row["flip_mean"]) == (61, 0.4, 0.04) and "provisional" not in row
    assert "Test GPU X" in row["measured"] and gpu["classes"]["gpu"]["provisional"] is False
    assert "Test GPU X" in gpu["classes"]["gpu"]["bounded_by"]
    assert gpu["references"]["3d"]["gpu"] == table["references"]["3d"]["gpu"]  # not measured: unchanged
    small = [verify.Row("stage", "triangle", "raw vs committed", "identical", Metrics(0, 0.0, 0, 0.0, 49152),
                        reference="triangle")]
    lava = verify.recalibrated(table, verify.Report("llvmpipe", "Intel", "lavapipe", "2026-11-24", small))
    before, after = table["references"]["triangle"]["lavapipe"], lava["references"]["triangle"]["lavapipe"]
    assert all(after[k] == before[k] for k in ("max_abs", "changed", "flip_mean"))
    assert after["measured"].startswith(before["measured"]) and "Intel" in after["measured"]
