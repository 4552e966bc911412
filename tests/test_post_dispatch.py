"""The dispatch shape of each compute post pass (core/plan/dispatch.py) and FXAA's workgroup tile.

The plan gives every compute pass its own shape; with post_intermediate = none, FXAA's pass recomputes the
tone-mapped texels once per texel of a workgroup tile (``PostPass.tile``), and a benchmark may tile the plain FXAA
pass too. Neither may change a pixel: the tiled image must equal, byte for byte, the same pass with every
texel read (or recomputed) where it is used, at sizes where tiles are cut by the image's edges, and at a size
smaller than one tile. How far the tiled image is from the truth is tests/test_post_intermediate.py's (float64)
and tests/test_post_paths.py's (the unfused fragment chain).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.plan import resolve_plan

SCENES = Path(__file__).resolve().parent.parent / "assets" / "scenes"
FINAL, SUBPASS = SCENES / "final.toml", SCENES / "final_subpass.toml"


def test_each_compute_pass_gets_the_shape_of_what_it_does():
    final = resolve_plan(FINAL, None, size=(640, 480), post_path="compute")
    tonemap, fxaa = final.post_passes
    # tonemap writes rgba16float (8 bytes a texel): square 8x8 groups, 2 rows each; FXAA too (it reads neighbours)
    assert (tonemap.effect, tonemap.output_format, tonemap.shape, tonemap.tile) == (
        "tonemap", "rgba16float", (8, 8, 2), "")
    # FXAA reading the stored image reads the texture: both tiles lost on the H100 (core/plan/dispatch.py)
    assert (fxaa.effect, fxaa.shape, fxaa.tile) == ("fxaa+vignette", (8, 8, 2), "")
    (fused,) = resolve_plan(SUBPASS, None, size=(640, 480), post_path="compute").post_passes
    assert (fused.effect, fused.output_format, fused.shape, fused.tile) == (
        "tonemap+vignette", "rgba8unorm", (32, 8, 4), "")
    (one,) = resolve_plan(FINAL, None, size=(640, 480), post_path="compute", post_intermediate="none").post_passes
    assert (one.effect, one.prelude, one.shape, one.tile) == ("tonemap+fxaa+vignette", 1, (8, 8, 1), "texels")
    assert "recomputes its 8x8 tile" in one.shape_why
    fragment = resolve_plan(FINAL, None, size=(640, 480), post_path="fragment")
    assert all(p.shape is None and p.tile == "" for p in fragment.post_passes)
    none_fragment = resolve_plan(FINAL, None, size=(640, 480), post_path="fragment", post_intermediate="none")
    (recomputed,) = none_fragment.post_passes
    assert (recomputed.prelude, recomputed.shape, recomputed.tile) == (1, None, "")  # a fragment pass: no tile


def test_explain_shows_each_dispatch():
    text = resolve_plan(FINAL, None, size=(640, 480), post_path="compute").explain()
    assert "dispatch: workgroups of 8x8, 2 row(s) per invocation (a per-pixel pass writing rgba16float" in text
    assert "dispatch: workgroups of 8x8, 2 row(s) per invocation (a neighbourhood pass" in text
    none = resolve_plan(FINAL, None, size=(640, 480), post_path="compute", post_intermediate="none").explain()
    assert "dispatch: workgroups of 8x8, 1 row(s) per invocation (each workgroup recomputes its 8x8 tile" in none
    assert "dispatch:" not in resolve_plan(FINAL, None, size=(640, 480), post_path="fragment").explain()


def test_the_tile_fits_webgpus_workgroup_memory():
    from wgpurender.bench.post_roofline import SHAPES, sweep_cases
    from wgpurender.core.plan.dispatch import RECOMPUTED, tile_fits, tile_texels

    assert tile_texels((16, 16, 2)) == (18, 34) and tile_texels(RECOMPUTED) == (10, 10)
    assert tile_fits(RECOMPUTED) and tile_fits((16, 16, 2)) and 18 * 34 * 16 <= 16384
    assert not tile_fits((32, 8, 4))  # 34 x 34 texels of 16 bytes = 18,496 > 16,384
    assert tile_fits((32, 8, 4), "luma") and not tile_fits((256, 1, 16), "luma")  # 4 bytes: 4,624; 258 x 18 x 4
    fxaa = resolve_plan(FINAL, None, size=(64, 48), post_path="compute").post_passes[1]
    cases = sweep_cases(fxaa, SHAPES)
    assert ((32, 8, 4), "texels") not in cases and ((32, 8, 4), "") in cases and ((16, 16, 2), "texels") in cases
    assert ((32, 8, 4), "luma") in cases and ((32, 8, 4), "edges") in cases and len(cases) == 4 * len(SHAPES) - 1
    tonemap = resolve_plan(FINAL, None, size=(64, 48), post_path="compute").post_passes[0]
    assert sweep_cases(tonemap, SHAPES) == [(s, "") for s in SHAPES]
    (one,) = resolve_plan(FINAL, None, size=(64, 48), post_path="compute", post_intermediate="none").post_passes
    assert not any(kind == "luma" for _, kind in sweep_cases(one, SHAPES))  # its taps need the texels


def test_the_shader_declares_the_tile_only_where_the_plan_says():
    from wgpurender.wgpu_path.post.shaders import pass_source

    tonemap, fxaa = resolve_plan(FINAL, None, size=(64, 48), post_path="compute").post_passes
    (one,) = resolve_plan(FINAL, None, size=(64, 48), post_path="compute", post_intermediate="none").post_passes
    assert "var<workgroup> tile: array<vec4f, 100>" in pass_source(one)  # 10 x 10 texels
    # the tile starts one texel (the apron) above and left of the workgroup's first pixel; reads outside the tile
    # recompute, so a tile without its apron draws the same image, only slower: checked in the text
    assert "tile_origin = vec2i(corner) - vec2i(1, 1);" in pass_source(one)
    assert "@workgroup_size(8, 8)" in pass_source(one) and "k < 1u" in pass_source(one)
    assert "var<workgroup>" not in pass_source(one, tiled="")
    assert "var<workgroup>" not in pass_source(fxaa, tiled="") and "var<workgroup>" not in pass_source(tonemap)
    # FXAA's pass through a tile of lumas: 10 x 18 (8 x 16 pixels and the apron), of which 52 are the apron's
    lumas = pass_source(fxaa, tiled="luma")
    assert "var<workgroup> luma_tile: array<f32, 180>" in lumas and "j < 52u" in lumas
    assert "@workgroup_size(8, 8)" in pass_source(fxaa) and "k < 2u" in pass_source(fxaa)
    tiled = pass_source(fxaa, (16, 8, 2), tiled="texels")  # a benchmark's tile: 18 x 18 texels, 16 x 16 pixels
    assert "var<workgroup> tile: array<vec4f, 324>" in tiled and "vec2u(16u, 16u)" in tiled
    with pytest.raises(ValueError, match="no FXAA reads to tile with 'texels'"):
        pass_source(tonemap, tiled="texels")
    with pytest.raises(ValueError, match="no FXAA reads to tile with 'luma'"):
        pass_source(one, tiled="luma")  # a recomputing pass's bilinear taps need its texels, not their lumas
    with pytest.raises(ValueError, match="no workgroup tile 'lumas': one of texels, luma"):
        pass_source(fxaa, tiled="lumas")


def _render(ctx, size, knob, monkeypatch, tiled, shape=None):
    """The image with FXAA's pass read through ``tiled`` ("" untiled) and dispatched with ``shape`` (the plan's
    if None); the other passes as planned."""
    import wgpurender.wgpu_path.post.passes as passes
    from wgpurender.wgpu_path.post.shaders import tileable
    from wgpurender.wgpu_path.scene import render_plan

    original = passes.pass_source

    def source(p, s=None, t=None):
        fxaa = tileable(p)
        return original(p, shape if fxaa else s, tiled if fxaa else "")

    monkeypatch.setattr(passes, "pass_source", source)
    if shape is not None:  # the dispatch must cover the image with the same shape as the shader's
        monkeypatch.setattr(passes, "shape_of", lambda p, s=None: shape if tileable(p) else (s or p.shape))
    plan = resolve_plan(FINAL, ctx.adapter_facts(), size=size, post_path="compute", post_intermediate=knob)
    assert plan.post_passes[-1].steps[plan.post_passes[-1].prelude].effect == "fxaa"
    image = render_plan(ctx, plan, frames=1).pixels
    monkeypatch.setattr(passes, "pass_source", original)
    return image


@pytest.mark.parametrize("knob,kind,shape", [("auto", "luma", None), ("auto", "texels", None),
                                              ("none", "texels", None), ("auto", "luma", (16, 4, 3)),
                                              ("auto", "luma", (32, 8, 1))])
@pytest.mark.parametrize("size", [(203, 117), (13, 7)])
def test_the_tiled_pass_draws_the_untiled_image(ctx, monkeypatch, knob, kind, shape, size):
    """(203, 117): tiles (8x16 pixels for auto, 8x8 for none) cut on the right and bottom; (13, 7): a partial tile.
    auto's pass is tiled as a benchmark may tile it (lumas, texels), none's as the plan does;
    the luma tile also with other shapes (its apron is shared out by index: rows of 3, 16 wide, 32 invocations)."""
    tiled = _render(ctx, size, knob, monkeypatch, kind, shape)
    untiled = _render(ctx, size, knob, monkeypatch, "", shape)
    assert tiled.shape == (size[1], size[0], 4) and (tiled[..., :3].astype(int).sum(-1) > 30).any(), "drawn"
    # every pixel written, the last partial workgroups' too (the clear colour's alpha is 1; a texel no
    # dispatch reached keeps the output's initial zeros)
    assert (tiled[..., 3] == 255).all() and (untiled[..., 3] == 255).all()
    assert np.array_equal(tiled, untiled), f"{int((tiled != untiled).any(-1).sum())} pixels differ"


def test_bench_shapes_are_parsed_or_refused_in_one_line():
    from wgpurender.core.errors import UserError
    from wgpurender.core.plan.dispatch import parse_shapes

    assert parse_shapes("16x8x2, 32X8X4,16x8x2") == ((16, 8, 2), (32, 8, 4))
    for bad, why in (("16x8", "is not WxHxR"), ("16x8x2,a", "'a' is not WxHxR"), ("32x16x1", "W*H between 1 and 256"),
                     ("0x8x1", "W*H between"), ("8x8x0", "1 to 16 rows"), ("8x8x17", "1 to 16 rows"),
                     ("8x8x\u00b2", "is not WxHxR")):  # '²' is a digit to str.isdigit, not to int()
        with pytest.raises(UserError, match=why):
            parse_shapes(bad)


def test_a_bad_bench_shape_is_one_line_and_exit_2(capsys, tmp_path):
    from wgpurender.cli import main

    code = main(["bench", "post-roofline", "--size", "32x24", "--shapes", "16x8", "--out", str(tmp_path / "out")])
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert code == 2 and len(err) == 1 and "'16x8' is not WxHxR" in err[0], err
    assert not (tmp_path / "out").exists()


def test_the_fastest_shape_per_pass_is_the_minimum_of_each_pass():
    from wgpurender.bench.post_roofline import PassTime, best_shapes

    rows = [PassTime("compute, fused", "tonemap", "compute", 1, 0.06, 0.05),
            PassTime("compute, fused", "fxaa+vignette", "compute", 1, 0.07, 0.04),
            PassTime("compute, fused, shape 8x8 x2 rows", "tonemap", "compute", 1, 0.060, 0.05),
            PassTime("compute, fused, shape 32x8 x4 rows", "tonemap", "compute", 1, 0.088, 0.05),
            PassTime("compute, fused, shape 8x8 x2 rows, untiled", "fxaa+vignette", "compute", 1, 0.073, 0.04),
            PassTime("compute, fused, shape 8x8 x2 rows, tiled", "fxaa+vignette", "compute", 1, 0.106, 0.04)]
    (line,) = best_shapes(rows)
    assert line.startswith("- fastest shape per pass (auto): tonemap 8x8 x2 rows 0.060 ms; fxaa+vignette 8x8 x2 "
                           "rows, untiled 0.073 ms; that chain 0.133 ms, ")
    assert f"{0.133 / 0.09:.2f}x a copy of the same bytes" in line
