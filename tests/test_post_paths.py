"""Fused vs unfused, compute vs fragment: the same chain's four images agree within 1/255.

Each repository scene with a post chain is rendered at 320x240 on the same machine in the same run, four
ways: unfused fragment passes (the reference: a pass and a texture per effect, the chain before issue 13),
fused fragment passes (the default), and both on the compute path. Tolerance: no channel off by more than
1/255 (the issue's bound); the share of differing pixels is bounded near what was measured.

Measured on lavapipe (Mesa 22.3, AMD EPYC), 2026-11-23, differing pixels of 76800, each by exactly 1/255:

| scene | fused fragment | unfused compute | fused compute |
|---|---|---|---|
| final.toml (tonemap, fxaa+vignette) | 1201 | 9605 | 10007 |
| final_subpass.toml (tonemap+vignette) | 2237 | 9558 | 10613 |
| retro.toml (tonemap+sepia+vignette, sharpen+srgb; rgba8unorm output) | 6363 | 0 | 6363 |

Why they differ at all: fused, the colour stays float32 between effects, where the unfused chain stores
it in rgba16float (lavapipe rounds that store toward zero; the fused chain is bit-identical to the raw
path's subpass, tests/test_vulkan_ref_scene.py). On the compute path an -srgb output cannot be a storage
texture, so the shader applies the sRGB curve and the image is copied, where the fragment path lets
lavapipe's (approximate) hardware encoder do it: retro.toml, whose rgba8unorm output is encoded by the
shader on both paths, is bit-identical between the unfused paths.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wgpurender.wgpu_path.scene import render_scene_file

SCENES = Path(__file__).resolve().parent.parent / "assets" / "scenes"
SIZE = (320, 240)
# scene -> the most differing pixels allowed (about 1.5x the measured worst of the three variants)
BOUNDS = {"final": 15000, "final_subpass": 16000, "retro": 9500}
VARIANTS = {"fused fragment": {"post_fuse": True, "post_path": "fragment"},
            "unfused compute": {"post_fuse": False, "post_path": "compute"},
            "fused compute": {"post_fuse": True, "post_path": "compute"}}


def render(ctx, name: str, **knobs) -> np.ndarray:
    return render_scene_file(SCENES / f"{name}.toml", size=SIZE, ctx=ctx, frames=1, knobs=knobs).pixels.astype(int)


@pytest.mark.parametrize("name", sorted(BOUNDS))
def test_fused_and_compute_chains_equal_the_unfused_chain(ctx, name):
    reference = render(ctx, name, post_fuse=False, post_path="fragment")
    assert (reference[..., :3].sum(-1) > 30).mean() > 0.2, "the scene is drawn"
    for label, knobs in VARIANTS.items():
        diff = np.abs(render(ctx, name, **knobs) - reference)
        differing = int((diff > 0).any(-1).sum())
        assert diff.max() <= 1, f"{name} {label}: a channel is off by {diff.max()}/255"
        assert differing <= BOUNDS[name], f"{name} {label}: {differing} pixels differ"


def test_compute_output_through_a_scratch_copy_is_the_same_image(ctx):
    """A swapchain image cannot be a storage texture (knob output_storage = off): the last compute pass then
    writes a scratch of the same format and copies it. Same shader, same bytes: exactly equal (rgba16float)."""
    direct = render_scene_file(SCENES / "final_subpass.toml", size=SIZE, fmt="rgba16float", ctx=ctx, frames=1,
                               knobs={"post_path": "compute"}).pixels
    copied = render_scene_file(SCENES / "final_subpass.toml", size=SIZE, fmt="rgba16float", ctx=ctx, frames=1,
                               knobs={"post_path": "compute", "output_storage": False}).pixels
    np.testing.assert_array_equal(copied, direct)
    assert np.isfinite(direct).all() and direct[..., :3].max() > 0.1


@pytest.mark.parametrize("name", ["final", "final_subpass"])
def test_srgb_output_written_as_its_twin_has_the_copy_paths_bytes(ctx, name):
    """Offscreen, an rgba8unorm-srgb output on the compute path is made as its rgba8unorm twin, which the last
    pass writes directly with the sRGB curve applied: no scratch, no copy (issue 31.4). Its readback must be
    byte for byte the image the scratch-and-copy path (what a swapchain still needs) puts into a real -srgb
    texture, and the fragment path's image within 1/255 (the hardware encoder there)."""
    from wgpurender.wgpu_path.scene import load_renderer

    twin = load_renderer(SCENES / f"{name}.toml", ctx, size=SIZE, knobs={"post_path": "compute"})
    last = twin.plan.post_passes[-1]
    assert (twin.plan.output_format, twin.plan.target_format) == ("rgba8unorm-srgb", "rgba8unorm")
    assert (last.output, last.output_format, last.twin_of, last.copy_to) == ("output", "rgba8unorm",
                                                                            "rgba8unorm-srgb", None)
    assert not twin.plan.has_attachment("post_scratch")
    assert twin.create_output().format == "rgba8unorm"
    direct = render(ctx, name, post_path="compute")
    copied_renderer = load_renderer(SCENES / f"{name}.toml", ctx, size=SIZE,
                                    knobs={"post_path": "compute", "output_storage": False})
    assert copied_renderer.plan.post_passes[-1].copy_to == "output"
    assert copied_renderer.create_output().format == "rgba8unorm-srgb"
    copied = render(ctx, name, post_path="compute", output_storage=False)
    np.testing.assert_array_equal(direct, copied)
    fragment = render(ctx, name, post_path="fragment")
    assert np.abs(direct - fragment).max() <= 1 and (direct[..., :3].sum(-1) > 30).mean() > 0.2


def test_a_hand_made_srgb_target_for_a_twin_plan_is_refused_in_one_line(ctx):
    """A plan whose output is the storage twin refuses a caller's -srgb texture by name (never a validation
    error or a silent copy), saying how to get the right one."""
    from wgpurender.core.errors import UserError
    from wgpurender.wgpu_path.device.targets import create_target
    from wgpurender.wgpu_path.scene import load_renderer

    renderer = load_renderer(SCENES / "final_subpass.toml", ctx, size=(32, 24), knobs={"post_path": "compute"})
    target = create_target(ctx, (32, 24), "rgba8unorm-srgb")
    encoder = ctx.device.create_command_encoder()
    with pytest.raises(UserError) as err:
        renderer.record(encoder, target)
    assert "storage twin rgba8unorm" in str(err.value) and "create_output()" in str(err.value)
    assert "\n" not in str(err.value)
