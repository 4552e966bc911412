"""The accuracy report compares the right pairs of images: each row against the ground truth, and against
its knob's top level ("FLIP vs knob top"), and writes each number into its own column.

No GPU: every setting of the sweep gets a synthetic flat grey image whose level is unique to it, so the
error of a pair says which two images were compared. Expected values: PSNR of two flat images by its
formula, FLIP through the flip-evaluator package called here directly, and the pairs from the rule stated
in the test (the ground truth is the top setting at 8x supersampling; a knob's row is paired with the same
setting with that knob at its highest level), not from the module's own pairing.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgpurender.bench.accuracy_knobs import Settings
from wgpurender.bench.accuracy_report import csv_row
from wgpurender.bench.accuracy_run import FINAL, Measurement, plan_cases, score
from wgpurender.wgpu_path.device.timing import Stats

SIZE = (24, 16)
# Written out here: the highest level of each knob, and the ground truth (all highest, 8x supersampled).
HIGHEST = {"msaa": 4, "format": "rgba32float", "filter": "aniso16", "depth": "reverse-z"}
TRUTH = Settings(msaa=4, ss=8, format="rgba16float", filter="aniso16", depth="reverse-z")


def _expected_isolated_ref(sweep: str, s: Settings) -> Settings | None:
    if sweep == "ss":
        return TRUTH
    if sweep in HIGHEST:
        return Settings(**{**s.__dict__, sweep: HIGHEST[sweep]})
    return None  # combinations and the ground truth row have no knob-top pair


def _flip(a: np.ndarray, b: np.ndarray) -> float:
    import flip_evaluator

    ref = np.ascontiguousarray(a[..., :3], np.float32) / 255.0
    test = np.ascontiguousarray(b[..., :3], np.float32) / 255.0
    return float(flip_evaluator.evaluate(ref, test, "LDR", applyMagma=False)[1])


def _psnr(level_a: int, level_b: int) -> float:
    return math.inf if level_a == level_b else 20 * math.log10(255.0 / abs(level_a - level_b))


@pytest.fixture(scope="module")
def scored():
    cases = [c for c in plan_cases() if c.scene == FINAL]
    keys = list(dict.fromkeys(c.key for c in cases))
    levels = {key: 20 + 9 * i for i, key in enumerate(keys)}  # a distinct grey per setting
    stats = Stats.of([1.0, 2.0])
    measured = {key: Measurement(np.full((SIZE[1], SIZE[0], 4), levels[key], np.uint8), SIZE, stats, stats, {})
                for key in keys}
    return [(c, score(c, measured, SIZE)) for c in cases], levels, measured


def test_every_row_is_compared_with_the_ground_truth(scored):
    rows, levels, measured = scored
    truth = (FINAL, TRUTH)
    assert truth in levels, "the sweep has no row for the 8x-supersampled top setting (the ground truth)"
    for case, row in rows:
        expected_psnr = _psnr(levels[truth], levels[case.key])
        assert row.psnr == pytest.approx(expected_psnr), (
            f"row '{case.sweep} {case.level}' ({case.settings.label()}): PSNR {row.psnr:.3f} dB is not its PSNR "
            f"against the ground truth ({expected_psnr:.3f} dB): it was compared with another image")
        expected_flip = _flip(measured[truth].pixels, measured[case.key].pixels)
        assert row.flip == pytest.approx(expected_flip, abs=1e-6), f"row '{case.sweep} {case.level}': FLIP pair"
        assert csv_row(row)["flip_mean"] == f"{expected_flip:.5f}", "accuracy.csv's flip_mean column"


def test_knob_rows_are_paired_with_their_knobs_top_level(scored):
    rows, levels, measured = scored
    checked = 0
    for case, row in rows:
        ref = _expected_isolated_ref(case.sweep, case.settings)
        if ref is None:
            assert math.isnan(row.flip_isolated), f"'{case.sweep} {case.level}' has no knob-top pair"
            continue
        key = (FINAL, ref)
        assert key in levels, f"row '{case.sweep} {case.level}': its knob-top setting {ref.label()} is not rendered"
        expected_flip = _flip(measured[key].pixels, measured[case.key].pixels)
        what = (f"row '{case.sweep} {case.level}' ({case.settings.label()}): 'FLIP vs knob top' must compare it "
                f"with {ref.label()}")
        assert row.psnr_isolated == pytest.approx(_psnr(levels[key], levels[case.key])), what
        assert row.flip_isolated == pytest.approx(expected_flip, abs=1e-6), what
        assert csv_row(row)["flip_vs_knob_top"] == f"{expected_flip:.5f}", "accuracy.csv's flip_vs_knob_top column"
        checked += 1
    assert checked >= 10  # every knob's levels were checked (msaa 2, ss 4, format 3, filter 5, depth 3)
