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
    knobs = ("rgba8unorm", "rgba8unorm-srgb", "none")
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
    # none: one pass, the HDR scene image read, the output written (tonemap recomputed for FXAA's reads)
    assert by[("compute, fused, none", "tonemap+fxaa+vignette")].bytes_moved == W * H * (8 + 4)
    assert all(r.ms > 0 and r.copy_ms > 0 and r.chain_wall_ms > 0 for r in rows)
    text = markdown(rows, ctx, FINAL, (W, H), 1, "test")
    assert "| fragment, fused | fxaa+vignette |" in text and "% of copy" in text
    assert "x a copy of the same bytes" in text and "the copy of the auto chain's bytes" in text


def test_chain_ratio_is_the_chains_time_over_the_copy_of_its_bytes():
    """Issue 31.6's figure from the second H100 run's rows: tonemap 0.089 ms (copy 0.049), fxaa+vignette 0.076 ms
    (copy 0.039): 0.165 / 0.088 = 1.875x. An 8-bit variant is also set against the auto chain's copy."""
    from wgpurender.bench.post_roofline import PassTime, chain_ratio

    auto = [PassTime("compute, fused", "tonemap", "compute", 1, 0.089, 0.049),
            PassTime("compute, fused", "fxaa+vignette", "compute", 1, 0.076, 0.039)]
    assert chain_ratio(auto) == pytest.approx(0.165 / 0.088)
    eight = [PassTime("compute, fused, rgba8unorm", "tonemap", "compute", 1, 0.05, 0.03, intermediate="rgba8unorm"),
             PassTime("compute, fused, rgba8unorm", "fxaa+vignette", "compute", 1, 0.06, 0.02,
                      intermediate="rgba8unorm")]
    assert chain_ratio(eight) == pytest.approx(0.11 / 0.05)
    from wgpurender.bench.post_roofline import _against_auto

    assert _against_auto(auto + eight, "compute, fused, rgba8unorm", eight) == (
        " (1.25x the copy of the auto chain's bytes)")
    assert _against_auto(auto + eight, "compute, fused", auto) == ""


def test_the_shape_sweep_covers_the_auto_and_the_one_pass_chain(ctx):
    """--shapes dispatches the fused compute passes with each shape, for the auto chain and post_intermediate none;
    FXAA's pass through its tile of texels (each shape whose tile fits 16 KB of workgroup memory: all but 32x8 x4),
    through its tile of lumas (4 bytes a texel: every shape), over an edge list (every shape), and untiled; the
    one-pass chain's has no luma tile (its bilinear taps need the texels)."""
    if not ctx.has("timestamp-query"):
        pytest.skip("no timestamp queries on this adapter")
    from wgpurender.bench.post_roofline import SHAPES

    rows = [r for r in run_roofline(ctx, FINAL, (16, 12), frames=1, shapes=True) if "shape" in r.variant]
    auto = [r for r in rows if r.intermediate == "auto"]
    none = [r for r in rows if r.intermediate == "none"]
    n = len(SHAPES)
    assert len(auto) == n + 4 * n - 1 and {r.effects for r in auto} == {"tonemap", "fxaa+vignette"}
    assert sum(r.variant.endswith(", edge list") for r in auto) == n
    assert sum(r.variant.endswith(", tiled") for r in auto) == n - 1
    assert sum(r.variant.endswith(", luma tile") for r in auto) == n
    assert not any(r.variant.endswith("tiled") for r in auto if r.effects == "tonemap")
    assert len(none) == 3 * n - 1 and {r.effects for r in none} == {"tonemap+fxaa+vignette"}
    assert all(r.variant.startswith("compute, fused, none, shape ") for r in none)
    text = markdown(rows, ctx, FINAL, (16, 12), 1, "test")
    assert "- fastest shape per pass (auto): tonemap " in text and "- fastest shape per pass (none): " in text


def test_a_scene_without_post_effects_is_one_line_and_exit_2(ctx, capsys, tmp_path):
    """A scene with no [[post]] block has no chain to time: the roofline made a query set of zero timestamps and
    the validation error was a traceback. The scene (a box, a camera, no [[post]]) is written here."""
    if not ctx.has("timestamp-query"):
        pytest.skip("no timestamp queries on this adapter: the command refuses that first")
    from wgpurender.cli import main
    from wgpurender.core.models import procedural

    procedural.write_obj(tmp_path / "box.obj", procedural.box(1.0))
    plain = tmp_path / "no_post.toml"
    plain.write_text('[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\n\n[[models]]\npath = "box.obj"\n')
    code = main(["bench", "post-roofline", str(plain), "--size", "32x24", "--frames", "1", "--out",
                 str(tmp_path / "out")])
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert code == 2 and len(err) == 1 and "has no [[post]] effects" in err[0], err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())  # no file written
