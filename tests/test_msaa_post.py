"""The msaa-post stage on both paths: raw Vulkan's two subpasses (input attachment) vs wgpu's two render passes.

Both run on lavapipe in this process with the same triangle, the same resolve and the same grey
formula (GLSL subpassLoad vs WGSL textureLoad of the stored resolve), so the images must be equal
bit for bit (threshold 0). Measured: 0 pixels differ at 800x600, 64x48 and 97x61 in every format.
The pixel values themselves are checked against numpy in tests/test_vulkan_ref.py
(test_msaa_post_is_grey_of_msaa), so equality here also checks the wgpu stage's values.
"""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.core.errors import UserError
from wgpurender.raw_path import render_reference

FORMATS = ["rgba8unorm-srgb", "rgba8unorm", "rgba16float"]


@pytest.mark.parametrize("size", [(64, 48), (97, 61)])
@pytest.mark.parametrize("fmt", FORMATS)
def test_msaa_post_matches_raw_subpasses(ctx, fmt, size):
    from wgpurender.wgpu_path.render import render_stage

    wgpu_pixels = render_stage("msaa-post", size, fmt, 4, 0.0, ctx, frames=1).pixels
    raw = render_reference("msaa-post", size, fmt, 4)
    assert wgpu_pixels.shape == raw.shape == (size[1], size[0], 4) and wgpu_pixels.dtype == raw.dtype
    rgb = wgpu_pixels[..., :3].astype(np.float64)
    assert (rgb.max(-1) > 0.05 * rgb.max()).sum() > 0.1 * size[0] * size[1]  # the triangle is there
    assert np.ptp(rgb, axis=-1).max() == 0  # grey everywhere
    assert np.array_equal(wgpu_pixels.view(np.uint8), raw.view(np.uint8)), (
        f"{np.count_nonzero((wgpu_pixels != raw).any(-1))} pixels differ")


def test_msaa_post_is_not_the_msaa_stage(ctx):
    """The post pass ran: the msaa stage's colour triangle became grey (so equality above is not two copies)."""
    from wgpurender.wgpu_path.render import render_stage

    msaa = render_stage("msaa", (64, 48), "rgba8unorm", 4, 0.0, ctx, frames=1).pixels
    post = render_stage("msaa-post", (64, 48), "rgba8unorm", 4, 0.0, ctx, frames=1).pixels
    assert np.ptp(msaa[..., :3].astype(int), axis=-1).max() > 100 and not np.array_equal(msaa, post)


def test_msaa_post_needs_msaa(ctx):
    from wgpurender.wgpu_path.render import render_stage

    with pytest.raises(UserError, match="use --msaa 4"):
        render_stage("msaa-post", (32, 24), "rgba8unorm", 1, 0.0, ctx, frames=1)


def test_cli_lists_and_renders_msaa_post(tmp_path, capsys):
    from wgpurender.cli import main
    from wgpurender.core.files.imageio import load_png

    assert main(["stages"]) == 0
    assert "msaa-post" in capsys.readouterr().out
    out = tmp_path / "x.png"
    assert main(["render", "msaa-post", "-o", str(out), "--size", "64x48"]) == 0
    assert np.array_equal(load_png(out), render_reference("msaa-post", (64, 48), "rgba8unorm-srgb", 4))


def test_declared_traffic_of_the_emulation():
    """wgpu's second pass declares two more full images per frame than the raw subpass: the resolve stored,
    then sampled. 800x600 rgba8: 1.92 MB (the output store) against 5.76 MB."""
    from wgpurender.bench.post import msaa_post_traffic

    assert msaa_post_traffic((800, 600)) == {"raw": 800 * 600 * 4, "wgpu": 3 * 800 * 600 * 4}
    assert msaa_post_traffic((10, 10), "rgba16float") == {"raw": 800, "wgpu": 2400}
