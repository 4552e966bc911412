"""``wgpurender verify --calibrate --size S`` measures one size class; the rows of the classes it did not measure
(and the targets it did not render) are kept, not dropped without a word (a review finding: before, the
implementation's whole entry was replaced by the one size measured). Each case builds its table at run time from
the calibration rule (tolerances.calibrate: CPU drivers, max = worst + 1 at least 2, changed and FLIP 2 x worst
at least 1% and 0.002; calibrate_structure: radial = worst + 1, detail = 2 x worst at least 0.02)."""

from __future__ import annotations

import tomllib

import pytest

from wgpurender import implementations
from wgpurender.core.errors import UserError
from wgpurender.core.verdict import tolerances
from wgpurender.core.verdict.structure import Structure
from wgpurender.core.verdict.tolerances import Metrics

SIZES = {"160x120": 19200, "320x240": 76800, "640x480": 307200}


def _spread(worst: int, pixels: int) -> Metrics:
    return Metrics(worst, 0.0, 0, 0.0, pixels)


@pytest.fixture()
def table(tmp_path, monkeypatch):
    """A browser entry calibrated at all three classes (max 3, 5, 9 -> 4, 6, 10; detail 0.03 -> 0.06), plus a
    second target 'clear' and another implementation's rows."""
    path = tmp_path / "implementations.toml"
    monkeypatch.setattr(tolerances, "IMPLEMENTATIONS_PATH", path)
    implementations.calibrate("wgpu-gl", {"160x120": {"final": (_spread(1, 19200), Structure(0.0, 0.0))}},
                              "gl run", "lavapipe")
    implementations.calibrate("browser", {
        size: {"final": (_spread(worst, pixels), Structure(0.0, 0.03)),
               "clear": (_spread(0, pixels), Structure(0.0, 0.0))}
        for (size, pixels), worst in zip(SIZES.items(), (3, 5, 9), strict=True)}, "first run", "lavapipe")
    return path


def _entry(path, impl="browser") -> dict:
    return tomllib.loads(path.read_text())["implementations"][impl]


def test_one_size_rewrites_its_class_and_keeps_the_others(table):
    before = _entry(table)["targets"]
    implementations.calibrate("browser", {"320x240": {"final": (_spread(20, 76800), Structure(0.0, 0.01))}},
                              "second run", "lavapipe")
    entry = _entry(table)
    row = entry["targets"]["final"]
    assert entry["size"] == "160x120" and row["max_abs"] == 4  # the base class, kept
    assert row["sizes"]["320x240"]["max_abs"] == 21  # measured now: worst 20 + 1
    assert row["sizes"]["640x480"] == before["final"]["sizes"]["640x480"]  # kept as it was
    assert entry["targets"]["clear"] == before["clear"]  # not rendered in this run: kept whole
    assert (row["radial"], row["detail"]) == (1.0, 0.06)  # 2 x 0.01 = 0.02 now, but the kept classes had 0.06
    assert "covered 160x120, 640x480" in row["structure_measured"]
    assert entry["bounded_by"] == "second run" and "first run" in entry["kept"] and "160x120, 640x480" in entry["kept"]
    assert _entry(table, "wgpu-gl")["bounded_by"] == "gl run"


def test_the_base_size_rewrites_the_base_row_and_keeps_the_larger_classes(table):
    implementations.calibrate("browser", {"160x120": {"final": (_spread(7, 19200), Structure(0.0, 0.2)),
                                                      "clear": (_spread(0, 19200), Structure(0.0, 0.0))}},
                              "base run", "lavapipe")
    row = _entry(table)["targets"]["final"]
    assert row["max_abs"] == 8 and sorted(row["sizes"]) == ["320x240", "640x480"]
    assert (row["sizes"]["320x240"]["max_abs"], row["sizes"]["640x480"]["max_abs"]) == (6, 10)
    assert row["detail"] == 0.4  # this run's 2 x 0.2 is above the kept 0.06


def test_every_size_measured_again_replaces_all_and_keeps_nothing(table):
    implementations.calibrate("browser", {
        size: {"final": (_spread(2, pixels), Structure(0.0, 0.0)), "clear": (_spread(0, pixels), Structure(0.0, 0.0))}
        for size, pixels in SIZES.items()}, "full run", "lavapipe")
    entry = _entry(table)
    assert "kept" not in entry and entry["targets"]["final"]["detail"] == 0.02
    assert [entry["targets"]["final"]["sizes"][s]["max_abs"] for s in ("320x240", "640x480")] == [3, 3]


def test_a_smaller_size_that_leaves_a_kept_target_without_a_base_row_is_one_line(table):
    text = table.read_text()
    with pytest.raises(UserError) as err:
        implementations.calibrate("browser", {"80x60": {"final": (_spread(1, 4800), Structure(0.0, 0.0))}},
                                  "tiny run", "lavapipe")
    assert "\n" not in str(err.value) and "clear" in str(err.value) and "80x60" in str(err.value)
    assert table.read_text() == text  # nothing written


def test_rows_of_another_driver_class_are_replaced_not_kept(table):
    implementations.calibrate("browser", {"320x240": {"final": (_spread(20, 76800), Structure(0.0, 0.01))}},
                              "gpu run", "gpu")
    entry = _entry(table)
    assert entry["size"] == "320x240" and list(entry["targets"]) == ["final"] and "kept" not in entry
