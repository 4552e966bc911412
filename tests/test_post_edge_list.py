"""FXAA over an edge list (issue 31.6; wgpurender/bench/fxaa_variants/edge_list.py): three dispatches, the
one-dispatch image.

``cs_mark`` writes every pixel off edges and lists the edge pixels, ``cs_size`` sizes the indirect dispatch and
zeroes the count, ``cs_edges`` runs FXAA on the listed pixels. The image must be the one-dispatch pass's, byte for
byte, at sizes that cut workgroups (one over 256 pixels wide: x is packed in 16 bits) and at shapes of 1 to 4
rows; the list must hold exactly the pixels FXAA's local-contrast test marks, counted here in numpy from the image
the pass reads; a second frame must list them again (the count is zeroed on the GPU, not by the CPU).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import wgpu

from wgpurender.core.plan import resolve_plan

FINAL = Path(__file__).resolve().parent.parent / "assets" / "scenes" / "final.toml"
LUMA_709 = np.array([0.2126, 0.7152, 0.0722], np.float32)


def _edges(rgb: np.ndarray, threshold: float, threshold_min: float) -> np.ndarray:
    """FXAA's local-contrast test (shaders_wgsl/post_fxaa.wgsl's is_edge): the clamped 4-neighbourhood of luma =
    sqrt(Rec. 709 luminance), an edge where max - min is not below max(threshold_min, max * threshold)."""
    lum = np.sqrt(np.maximum(rgb.astype(np.float32) @ LUMA_709, 0.0))
    pad = np.pad(lum, 1, mode="edge")
    h, w = lum.shape
    near = [pad[1 + dy:1 + dy + h, 1 + dx:1 + dx + w] for dx, dy in ((0, -1), (0, 1), (-1, 0), (1, 0))]
    l_max, l_min = np.maximum.reduce([lum, *near]), np.minimum.reduce([lum, *near])
    return ~(l_max - l_min < np.maximum(threshold_min, l_max * threshold))


def _run(ctx, runner, source, like) -> np.ndarray:
    """The runner's image into a new texture like ``like`` (zeros where no dispatch writes: a pixel left out shows,
    not the image an earlier run left there)."""
    from wgpurender.wgpu_path.device.targets import read_texture

    target = ctx.device.create_texture(size=like.size, format=like.format, usage=like.usage)
    encoder = ctx.device.create_command_encoder()
    runner.encode(encoder, source, target)
    ctx.queue.submit([encoder.finish()])
    return read_texture(ctx, target)


def _blocks(size: tuple[int, int], seed: int) -> np.ndarray:
    """An image of 0 / 0.25 / 1 grey blocks of 1-6 pixels: edges everywhere a block ends (contrast 0.5-1 of
    luma, far above FXAA's thresholds), flat inside; alpha 1."""
    rng = np.random.default_rng(seed)
    w, h = size
    xs, ys = np.cumsum(rng.integers(1, 7, w)), np.cumsum(rng.integers(1, 7, h))
    grey = rng.choice(np.float32([0.0, 0.25, 1.0]), (h + 1, w + 1))
    image = np.ones((h, w, 4), np.float32)
    image[..., :3] = grey[np.searchsorted(ys, np.arange(h), "right")][:, np.searchsorted(xs, np.arange(w), "right")][
        ..., None]
    return image


@pytest.mark.parametrize("size,shape", [((203, 117), None), ((13, 7), None), ((203, 117), (8, 8, 1)),
                                        ((301, 37), (32, 8, 1)), ((97, 61), (8, 8, 4))])
def test_the_edge_list_draws_the_one_dispatch_image_and_lists_the_edges(ctx, size, shape):
    from wgpurender.bench.fxaa_variants.edge_list import EdgeListPass
    from wgpurender.wgpu_path.post import PostChain, create_effect
    from wgpurender.wgpu_path.post.passes import ComputePass

    chain = PostChain([create_effect("fxaa"), create_effect("vignette")], path="compute")
    (p,) = chain.plan("rgba16float", "rgba8unorm", size)[0]
    image = _blocks(size, seed=size[0] + (shape or (0,))[0])
    source = ctx.device.create_texture(size=(*size, 1), format="rgba16float",
                                       usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST)
    ctx.queue.write_texture({"texture": source}, image.astype(np.float16).tobytes(),
                            {"bytes_per_row": size[0] * 8, "rows_per_image": size[1]}, (*size, 1))
    target = ctx.device.create_texture(size=(*size, 1), format=p.output_format,
                                       usage=wgpu.TextureUsage.STORAGE_BINDING | wgpu.TextureUsage.COPY_SRC)
    one = _run(ctx, ComputePass(ctx.device, p, shape, ""), source, target)
    edges = EdgeListPass(ctx.device, p, shape)
    params = dict(p.steps[0].params)
    expected = _edges(image[..., :3].astype(np.float16), float(params["edge_threshold"]),
                      float(params["edge_threshold_min"]))
    assert 0.05 * expected.size < expected.sum() < 0.95 * expected.size, "edges and flat pixels both"
    for frame in range(2):  # the count is zeroed on the GPU for the next frame
        listed = _run(ctx, edges, source, target)
        assert edges.listed() == int(expected.sum()), frame
        assert (listed[..., 3] == 255).all(), "every pixel written, off the list or from it"
        assert np.array_equal(listed, one), f"{int((listed != one).any(-1).sum())} pixels differ"


@pytest.mark.parametrize("knob", ["auto", "none"])
def test_final_tomls_fxaa_pass_over_an_edge_list_is_the_same_image(ctx, knob):
    """final.toml's FXAA pass, reading the stored tone-mapped image (auto) or recomputing it per texel (none)."""
    from wgpurender.bench.fxaa_variants.edge_list import EdgeListPass
    from wgpurender.core.scene import load_scene
    from wgpurender.wgpu_path.post.passes import ComputePass
    from wgpurender.wgpu_path.scene import SceneRenderer, render_frame

    scene = load_scene(FINAL)
    plan = resolve_plan(scene, ctx.adapter_facts(), size=(211, 93), post_path="compute", post_intermediate=knob)
    renderer = SceneRenderer(ctx, scene, plan)
    target = renderer.create_output()
    render_frame(ctx, renderer, target)
    textures = {**renderer.attachments, "output": target}
    p = plan.post_passes[-1]
    assert p.steps[p.prelude].effect == "fxaa" and p.prelude == (1 if knob == "none" else 0)
    source, out = textures[p.input], textures[p.output]
    one = _run(ctx, ComputePass(ctx.device, p, None, ""), source, out)
    edges = EdgeListPass(ctx.device, p)
    listed = _run(ctx, edges, source, out)
    assert 0 < edges.listed() < 211 * 93 // 2
    assert np.array_equal(listed, one), f"{int((listed != one).any(-1).sum())} pixels differ"


def test_a_pass_without_fxaa_or_an_image_too_wide_is_refused(ctx):
    from wgpurender.bench.fxaa_variants.edge_list import EdgeListPass
    from wgpurender.core.errors import UserError

    tonemap, fxaa = resolve_plan(FINAL, None, size=(64, 48), post_path="compute").post_passes
    with pytest.raises(ValueError, match="no FXAA to run over an edge list"):
        EdgeListPass(ctx.device, tonemap)
    with pytest.raises(UserError, match="up to 65535 pixels a side, not 65536x2"):
        EdgeListPass(ctx.device, fxaa)._list((65536, 2))
