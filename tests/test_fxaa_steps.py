"""FXAA's two draws on the fragment path (mark edges in depth, then FXAA depth-tested on edge pixels;
wgpurender/wgpu_path/post/shaders.py says why) give exactly the image of the single full-screen draw of the same
shader, whose early exit makes the same decision per pixel; and the compute path (one dispatch, no mask)
gives that image too. Bit-exact (array_equal): the same arithmetic on the same pixels."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from test_post import aliased_edge, hdr_image, run_chain, upload  # noqa: F401  (hdr_image is a fixture)

from wgpurender.wgpu_path.device.targets import create_target, read_texture
from wgpurender.wgpu_path.post import FragmentPass, PostChain, create_effect


def single_draw(ctx, img: np.ndarray, fmt: str = "rgba16float", **params) -> np.ndarray:
    """The planned FXAA pass with its mask removed: fs_main alone over every pixel (FXAA before issue 7)."""
    h, w = img.shape[:2]
    (p,), _ = PostChain([create_effect("fxaa", **params)]).plan("rgba16float", fmt, (w, h))
    assert p.mask == "fxaa_mask"
    runner = FragmentPass(ctx.device, dataclasses.replace(p, mask=None))
    assert len(runner.pipelines) == 1
    src, dst = upload(ctx, img), create_target(ctx, (w, h), fmt)
    encoder = ctx.device.create_command_encoder()
    runner.encode(encoder, src, dst)
    ctx.queue.submit([encoder.finish()])
    out = read_texture(ctx, dst)
    return out.astype(np.float64) if out.dtype != np.uint8 else out


@pytest.mark.parametrize("fmt", ["rgba16float", "rgba8unorm-srgb"])
def test_two_draws_equal_one_draw_on_an_aliased_edge(ctx, fmt):
    img = aliased_edge()
    two = run_chain(ctx, [create_effect("fxaa")], img, fmt)
    one = single_draw(ctx, img, fmt)
    np.testing.assert_array_equal(two, one)
    full = 255.0 if fmt.startswith("rgba8") else 1.0
    assert ((two[..., 0] > 0.02 * full) & (two[..., 0] < 0.98 * full)).any(), "FXAA blended some pixels"


def test_two_draws_equal_one_draw_and_compute_on_noise(ctx, hdr_image):  # noqa: F811
    """Random HDR values: a mix of edge and flat pixels at every threshold, clamped borders included."""
    img = hdr_image.copy()
    img[:, :8] = 0.5  # a flat band, where draw 2 must not write
    two = run_chain(ctx, [create_effect("fxaa", edge_threshold=0.3)], img)
    one = single_draw(ctx, img, edge_threshold=0.3)
    np.testing.assert_array_equal(two, one)
    np.testing.assert_array_equal(two[:, :7], img[:, :7].astype(np.float64))
    compute = run_chain(ctx, [create_effect("fxaa", edge_threshold=0.3)], img, path="compute")
    np.testing.assert_array_equal(compute, one)
