"""benchmarks/post_interleave.py's grouping by SM clock (issue 31.6): the H100's clock is not locked and fell from
1980 to 1080 MHz within one run (docs/perf-h100/2026-11-27-post4/), so a run's rows are compared at one clock. The
rows here are made up; the expected medians and chain ratios are computed from them by hand."""

from __future__ import annotations

from helpers import benchmark_script


def _module():
    return benchmark_script("post_interleave")


def _rows():
    """(round, case, frame, ms, clock): rounds 0-1 at 1980 MHz, round 2 at 1080; three frames a case a round."""
    times = {"copy (chain bytes)": (0.08, 0.09), "tonemap (plan)": (0.06, 0.08), "fxaa main": (0.07, 0.12),
             "fxaa luma 8x8x2": (0.11, 0.17)}
    rows = []
    for rnd, clock in ((0, "1980"), (1, "1980"), (2, "1080")):
        for case, (fast, slow) in times.items():
            base = fast if clock == "1980" else slow
            rows += [(rnd, case, f, base + d, clock) for f, d in enumerate((0.0, 0.001, 0.05))]  # median: +0.001
    return rows


def test_each_case_is_summarised_per_clock_and_the_chain_over_the_copy():
    text = _module().by_clock(_rows())
    assert "| case | 1980 (2) | 1080 (1) |" in text  # the higher clock first, with its number of rounds
    assert "| fxaa main | 0.0710 | 0.1210 |" in text
    assert "| copy (chain bytes) | 0.0810 | 0.0910 |" in text
    # (tonemap + fxaa) / copy at each clock: (0.061 + 0.071) / 0.081, (0.081 + 0.121) / 0.091
    assert (f"- tonemap + fxaa main over the copy: {0.132 / 0.081:.3f}x at 1980, {0.202 / 0.091:.3f}x at 1080"
            in text)
    assert f"- tonemap + fxaa luma 8x8x2 over the copy: {0.172 / 0.081:.3f}x at 1980" in text
    assert "- tonemap + copy" not in text and "- tonemap + tonemap" not in text  # only FXAA cases make chains


def test_a_case_missing_at_a_clock_has_no_chain_line():
    rows = [r for r in _rows() if not (r[1] == "fxaa luma 8x8x2" and r[4] == "1080")]
    text = _module().by_clock(rows)
    assert "| fxaa luma 8x8x2 | 0.1110 |  |" in text
    assert "- tonemap + fxaa luma 8x8x2" not in text and "- tonemap + fxaa main" in text
