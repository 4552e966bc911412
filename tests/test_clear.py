"""Course step 1: clearing, with and without a render pass, at sizes that need row padding."""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.core.course.triangle import CLEAR_COLOR
from wgpurender.core.files.imageio import srgb_encode
from wgpurender.wgpu_path.device.targets import create_target, read_texture
from wgpurender.wgpu_path.render import render_stage
from wgpurender.wgpu_path.stages import get_stage

ODD_SIZES = [(257, 13), (1, 1), (63, 65)]  # 257 * 4 bytes = 1028: not a multiple of 256


@pytest.mark.parametrize("size", ODD_SIZES)
def test_clear_pass_unorm_exact(ctx, size):
    """Every pixel is exactly the clear colour (k/255 values convert to unorm exactly)."""
    pixels = render_stage("clear-pass", size, "rgba8unorm", ctx=ctx, frames=1).pixels
    expected = np.round(np.array(CLEAR_COLOR) * 255).astype(np.uint8)
    assert pixels.shape == (size[1], size[0], 4)
    assert (pixels == expected).all()


def test_clear_pass_srgb_and_float(ctx):
    """sRGB targets store the encoded colour (within 1 unit: the driver's rounding); float16 stores it as is."""
    srgb = render_stage("clear-pass", (257, 13), "rgba8unorm-srgb", ctx=ctx, frames=1).pixels.astype(int)
    encoded = np.round(srgb_encode(np.array(CLEAR_COLOR[:3])) * 255)
    assert np.abs(srgb[..., :3] - encoded).max() <= 1
    assert (srgb[..., :3] == srgb[0, 0, :3]).all()
    half = render_stage("clear-pass", (257, 13), "rgba16float", ctx=ctx, frames=1).pixels
    assert (half == np.array(CLEAR_COLOR, dtype=np.float16)).all()


@pytest.mark.parametrize("size", ODD_SIZES)
def test_clear_without_render_pass_overwrites_everything(ctx, size):
    """Fill the target with a colour through a render pass, then the transfer clear must zero every texel."""
    target = create_target(ctx, size, "rgba8unorm")
    fill = get_stage("clear-pass")(ctx, "rgba8unorm")
    clear = get_stage("clear")(ctx, "rgba8unorm")
    encoder = ctx.device.create_command_encoder()
    fill.record(encoder, target)
    ctx.queue.submit([encoder.finish()])
    assert (read_texture(ctx, target) != 0).any()
    encoder = ctx.device.create_command_encoder()
    clear.record(encoder, target)
    ctx.queue.submit([encoder.finish()])
    assert (read_texture(ctx, target) == 0).all()
