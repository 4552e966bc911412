"""The report's "what each knob is for" section (wgpurender/report/teaching.py), from measurements made here by
hand: the still-frame explanation in the words docs/accuracy.md carries, and each table holding exactly the
rows it is about."""

from __future__ import annotations

import html
from types import SimpleNamespace

from wgpurender.bench.accuracy_shimmer import ShimmerRow
from wgpurender.bench.accuracy_teaching import HDR, SHIMMER, STILL_FRAME
from wgpurender.report import teaching
from wgpurender.report.extras import Point


def _measured():
    accuracy = [Point("msaa", "1", 0.04, 30.0, 1.0), Point("msaa", "4", 0.0401, 30.0, 2.0),
                Point("filter", "nearest", 0.027, 32.0, 1.0), Point("filter", "trilinear", 0.043, 30.0, 1.0),
                Point("ss", "2x", 0.02, 37.0, 4.0)]
    hard = [Point("HDR target", "rgba8unorm-srgb", 0.14, 27.05, 0.5),
            Point("HDR target", "rgba16float", 0.01, 58.2, 0.5),
            Point("shading precision", "rgba16float", 0.008, 59.07, 0.5)]
    shimmer = [ShimmerRow("edges", "none", 0.0079, 0.0074, 0.0047),
               ShimmerRow("minified plane", "trilinear", 0.0279, 0.0258, 0.084)]
    return SimpleNamespace(accuracy=accuracy, hard_cases=hard, shimmer=shimmer, shimmer_size=(64, 48),
                           shimmer_frames=4)


def test_the_section_explains_and_shows_each_case():
    page = teaching.section(_measured())
    for text in (STILL_FRAME, SHIMMER, HDR):
        assert html.escape(text) in page
    still = page[page.index('class="teaching-still"'):page.index("</table>", page.index('class="teaching-still"'))]
    assert still.count("<tr><td>") == 4 and "2x" not in still  # the MSAA and filter rows only
    assert '<td>nearest</td><td>0.0270</td>' in still
    shimmer = page[page.index('class="teaching-shimmer"'):]
    assert '<td>minified plane</td><td>trilinear</td><td>0.0279</td><td>0.0258</td>' in shimmer
    assert '<td>edges</td><td>none</td><td>0.0079</td>' in shimmer
    hdr = page[page.index('class="teaching-hdr"'):]
    assert "<td>rgba16float</td><td>0.0100</td><td>58.20</td>" in hdr and "59.07" not in hdr
    assert "64x48, 4 frames" in page


def test_without_measurements_the_section_says_so():
    page = teaching.section(None)
    assert 'id="teaching"' in page and "Not measured" in page and "<table" not in page
