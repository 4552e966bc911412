"""``wgpurender bench post-roofline`` runs on any adapter and reports the bytes each pass must move.

Bytes are checked against formulas written here: final.toml at 64x48, tonemap reads and writes rgba16float
(8 bytes a pixel each way); the fused fxaa+vignette fragment pass reads rgba16float, writes rgba8unorm-srgb
(4) and writes and tests FXAA's depth16unorm mask (2 + 2). Times are only checked to be measured (positive):
speed is for benchmarks, not tests.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from wgpurender.bench.post_roofline import markdown, run_roofline

FINAL = Path(__file__).resolve().parent.parent / "assets" / "scenes" / "final.toml"
W, H = 64, 48


def test_roofline_rows_cover_every_variant_with_the_planned_bytes(ctx):
    if not ctx.has("timestamp-query"):
        pytest.skip("no timestamp queries on this adapter")
    rows = run_roofline(ctx, FINAL, (W, H), frames=1)
    by = {(r.variant, r.effects): r for r in rows}
    variants = {"fragment, unfused", "fragment, fused", "compute, unfused", "compute, fused"}
    knobs = ("rgba8unorm", "rgba8unorm-srgb")
    assert set(v for v, _ in by) == variants | {f"{v}, {k}" for v in variants for k in knobs}
    assert by[("fragment, unfused", "tonemap")].bytes_moved == W * H * (8 + 8)
    assert by[("fragment, fused", "fxaa+vignette")].bytes_moved == W * H * (8 + 2 + 4 + 2)
    # on the compute path the -srgb output is written directly as its rgba8unorm twin: 4 bytes, no copy after it
    fused_compute = by[("compute, fused", "fxaa+vignette")]
    assert (fused_compute.bytes_moved, fused_compute.copy_bytes) == (W * H * (8 + 4), 0)
    # post_intermediate = rgba8unorm: tonemap writes 4 bytes a pixel and FXAA reads 4
    assert by[("compute, fused, rgba8unorm", "tonemap")].bytes_moved == W * H * (8 + 4)
    assert by[("compute, fused, rgba8unorm", "fxaa+vignette")].bytes_moved == W * H * (4 + 4)
    # rgba8unorm-srgb on the compute path: tonemap's rgba8unorm scratch is copied into it (4 + 4 bytes, untimed)
    encoded = by[("compute, fused, rgba8unorm-srgb", "tonemap")]
    assert (encoded.bytes_moved, encoded.copy_bytes) == (W * H * (8 + 4), W * H * (4 + 4))
    assert all(r.ms > 0 and r.copy_ms > 0 and r.chain_wall_ms > 0 for r in rows)
    text = markdown(rows, ctx, FINAL, (W, H), 1, "test")
    assert "| fragment, fused | fxaa+vignette |" in text and "% of copy" in text
    assert "x a copy of the same bytes" in text and "the copy of the auto chain's bytes" in text
