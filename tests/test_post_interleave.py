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


def test_a_gather_case_chains_with_the_tonemap_that_writes_its_lumas():
    """--set gather: FXAA reading lumas from alpha runs after "tonemap luma", so its chain is that pass + it."""
    rows = _rows()
    rows += [(r, "tonemap luma", f, ms + 0.002, c) for r, case, f, ms, c in _rows() if case == "tonemap (plan)"]
    rows += [(r, "fxaa gather 8x8x2", f, ms - 0.03, c) for r, case, f, ms, c in _rows() if case == "fxaa main"]
    text = _module().by_clock(rows)
    # (0.063 + 0.041) / 0.081 at 1980, (0.083 + 0.091) / 0.091 at 1080
    assert (f"- tonemap luma + fxaa gather 8x8x2 over the copy: {0.104 / 0.081:.3f}x at 1980, "
            f"{0.174 / 0.091:.3f}x at 1080") in text
    assert f"- tonemap + fxaa main over the copy: {0.132 / 0.081:.3f}x at 1980" in text


def test_an_image_differing_says_how_many_pixels_and_by_how_much():
    import numpy as np

    verdict = _module().image_verdict
    ref = np.zeros((4, 5, 4), np.uint8)
    assert verdict(ref.copy(), ref) == "yes"
    img = ref.copy()
    img[0, 0, 1], img[2, 3, 3], img[3, 4, 0] = 1, 3, 250  # three pixels, 1, 3 and 250 steps
    assert verdict(img, ref) == "NO (3 px, max 250, > 1: 2)"
