"""FXAA's luma in the intermediate's alpha (issue 31.6; wgpurender/bench/fxaa_variants/luma_alpha.py), against
independent values.

The tonemap variant must store the plan's colour unchanged and, in alpha, sqrt(Rec. 709 luminance) of that stored
colour (numpy here, from the f16 texels read back, to one f16 step); the FXAA variant, given those lumas, must draw
the plan's FXAA image byte for byte, on images far from FXAA's threshold (a wrong gather component moves edges) and
on noise whose contrast straddles it (without the slack for the lumas' f16 rounding some of its pixels differ:
a mutation row removes it); and the chain of tests/test_post_intermediate.py's quad scene must be the plan's image.
"""

from __future__ import annotations

import numpy as np
import pytest
import test_post_intermediate as case
import wgpu
from test_post_edge_list import FINAL, _blocks, _run

from wgpurender.core.plan import resolve_plan
from wgpurender.core.scene import load_scene

LUMA_709 = np.array([0.2126, 0.7152, 0.0722], np.float32)


@pytest.fixture(scope="module")
def drawn(ctx, tmp_path_factory):
    from wgpurender.bench.fxaa_variants.luma_alpha import draw_chain
    from wgpurender.wgpu_path.device.targets import read_texture
    from wgpurender.wgpu_path.post.passes import ComputePass
    from wgpurender.wgpu_path.scene import SceneRenderer, render_frame

    path = case.write_scene(tmp_path_factory.mktemp("luma-alpha"))
    plan = resolve_plan(load_scene(path), ctx.adapter_facts(), post_path="compute")
    renderer = SceneRenderer(ctx, load_scene(path), plan)
    target = renderer.create_output()
    plan_image = render_frame(ctx, renderer, target)[0]
    middle = draw_chain(ctx, renderer, target)
    first = plan.post_passes[0]  # the plan's tonemap again, into a readable texture like the variant's
    stored = _run(ctx, ComputePass(ctx.device, first), renderer.attachments[first.input], middle)
    return plan_image, read_texture(ctx, target), stored, read_texture(ctx, middle)


def test_the_intermediate_holds_the_plan_colour_and_the_luma_of_it(drawn):
    _, _, stored, middle = drawn
    assert middle.dtype == np.float16 and np.array_equal(middle[..., :3], stored[..., :3])
    want = np.sqrt(np.maximum(middle[..., :3].astype(np.float32) @ LUMA_709, 0.0))
    # within one f16 step of the value: the store rounds the f32 luma (lavapipe: towards zero at 16% of these
    # pixels, measured) and the GPU's square root need not be numpy's to the last bit
    step = np.spacing(want.astype(np.float16)).astype(np.float32)
    off = np.abs(middle[..., 3].astype(np.float32) - want) / step
    assert off.max() <= 1.0, off.max()
    assert np.unique(want).size >= 10  # the scene has its ten colours, not one


def test_the_variant_draws_the_plan_image_and_is_as_close_to_the_float64_chain(drawn):
    """The plan's image byte for byte (alpha 1 here, as the variant writes), so within the plan image's calibrated
    tolerance against the float64 chain (case.AUTO_MAX, AUTO_OVER1)."""
    plan_image, variant, _, _ = drawn
    assert np.array_equal(variant, plan_image), int((variant != plan_image).any(-1).sum())
    want = case.truth()
    got = case.errors(variant.astype(np.float64), want)
    assert got["max"] <= case.AUTO_MAX and got["over1"] <= case.AUTO_OVER1, got
    assert (variant[..., 3] == 255).all() and (plan_image[..., 3] == 255).all()


def _noise(size: tuple[int, int], seed: int) -> np.ndarray:
    """Colour noise (each channel 0.22-0.38): lumas about 0.55, whose local contrast is spread around FXAA's
    threshold there (max(0.0833, 0.166 * 0.55) = 0.091), so the f16 rounding of the stored lumas matters; alpha 1."""
    rng = np.random.default_rng(seed)
    image = np.ones((size[1], size[0], 4), np.float32)
    image[..., :3] = rng.uniform(0.22, 0.38, (size[1], size[0], 3))
    return image


def _straddle(size: tuple[int, int], seed: int) -> np.ndarray:
    """A checkerboard of greys with lumas 0.6 and 0.5004 (contrast 0.0996 = 0.166 * 0.6, FXAA's threshold at
    0.6), each channel jittered by up to 0.1% (about one f16 step of luma): nearly every pixel's contrast test
    is decided within the lumas' rounding; alpha 1."""
    rng = np.random.default_rng(seed)
    ys, xs = np.mgrid[0:size[1], 0:size[0]]
    grey = np.where((xs + ys) % 2 == 0, 0.36, 0.5004 ** 2)
    image = np.ones((size[1], size[0], 4), np.float32)
    image[..., :3] = grey[..., None] * rng.uniform(0.999, 1.001, (size[1], size[0], 3))
    return image


@pytest.mark.parametrize("pattern,size,shape", [(_blocks, (203, 117), None), (_blocks, (97, 61), (8, 8, 4)),
                                                (_blocks, (13, 7), (16, 8, 1)), (_noise, (203, 117), None),
                                                (_noise, (64, 48), (8, 8, 1)), (_straddle, (256, 160), None)])
def test_gathered_lumas_draw_the_plan_fxaa_image(ctx, pattern, size, shape):
    """Given each texel's luma in alpha (numpy: sqrt of the Rec. 709 luminance of the f16 colour, rounded to f16),
    the variant must draw what the plan's FXAA draws from the colour, byte for byte, borders (clamped) included:
    on grey blocks (lumas 0, 0.5, 1: far from the threshold) and on noise whose contrast straddles it (the
    pixels where the f16 lumas alone would decide otherwise must be recomputed), and a checkerboard on it."""
    from wgpurender.bench.fxaa_variants.luma_alpha import LumaAlphaPass
    from wgpurender.wgpu_path.post import PostChain, create_effect
    from wgpurender.wgpu_path.post.passes import ComputePass

    chain = PostChain([create_effect("fxaa"), create_effect("vignette")], path="compute")
    (p,) = chain.plan("rgba16float", "rgba8unorm", size)[0]
    image = pattern(size, seed=size[1])
    with_luma = image.astype(np.float16).astype(np.float32)
    with_luma[..., 3] = np.sqrt(with_luma[..., :3] @ LUMA_709)
    usage = wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST
    sources = []
    for pixels in (image, with_luma):
        sources.append(ctx.device.create_texture(size=(*size, 1), format="rgba16float", usage=usage))
        ctx.queue.write_texture({"texture": sources[-1]}, pixels.astype(np.float16).tobytes(),
                                {"bytes_per_row": size[0] * 8, "rows_per_image": size[1]}, (*size, 1))
    like = ctx.device.create_texture(size=(*size, 1), format=p.output_format,
                                     usage=wgpu.TextureUsage.STORAGE_BINDING | wgpu.TextureUsage.COPY_SRC)
    plain = _run(ctx, ComputePass(ctx.device, p, shape, ""), sources[0], like)
    gathered = _run(ctx, LumaAlphaPass(ctx.device, p, "fxaa", shape), sources[1], like)
    assert np.array_equal(gathered, plain), int((gathered != plain).any(-1).sum())


def test_each_variant_refuses_the_other_pass_and_a_changed_shader():
    from wgpurender.bench.fxaa_variants.luma_alpha import exchange, fxaa_gather_source, tonemap_luma_source

    plan = resolve_plan(str(FINAL), None,
                        size=(64, 32), post_path="compute")
    tonemap, fxaa = plan.post_passes
    with pytest.raises(ValueError, match="written by a per-pixel"):
        tonemap_luma_source(fxaa)
    with pytest.raises(ValueError, match="read by an FXAA"):
        fxaa_gather_source(tonemap)
    with pytest.raises(ValueError, match="found 0"):
        exchange("fn a() {}", "let l_m = 1.0;\n", "")
    with pytest.raises(ValueError, match="found 2"):
        exchange("x;\nx;\n", "x;\n", "y;\n")
    assert "stored_luma(c.rgb)" in tonemap_luma_source(tonemap)
    assert fxaa_gather_source(fxaa).count("textureGather(3, src") == 2
