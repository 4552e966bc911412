"""The final scene on the raw-Vulkan path (wgpurender.raw_path.scene) against the wgpu path, and its refusals.

The raw path draws a scene file the course's way: one render pass, subpass 0 draws the models
into the 4x MSAA rgba16float attachment (resolve + MSAA depth), subpass 1 reads the resolved image
as an input attachment and runs the post chain's per-pixel effects in ONE fragment shader. The
wgpu path draws the same plan with a separate render pass per effect when the plan is unfused
(post_fuse = false, used below to measure the float16 intermediates); fused, its default, it composes
per-pixel effects in one pass like the subpass, and is bit-identical to it. Both run on lavapipe.

What was measured (320x240 unless said otherwise, lavapipe / Mesa 22.3):

- The scene image itself (no post chain, rgba16float output) is bit-identical at msaa 1 and 4:
  same sample positions and resolve, same sRGB decoding and filtering of the textures (combined
  image samplers on the raw path, separate ones on wgpu: sampled alike), the same mip chains, the
  same float32 shading (GLSL from glslc and WGSL from naga compile to the same operations), and
  the same std140 bytes from two independent packers.
- Every post effect alone is bit-identical (tonemap, vignette, grayscale, sepia, srgb; float and
  8-bit outputs).
- The one difference is composing effects: the raw path keeps the colour in float32 registers
  from one effect to the next, the wgpu path stores it in an rgba16float texture between its
  passes, and lavapipe stores float32 -> float16 by rounding toward zero. final_subpass.toml
  (tonemap -> vignette): 2697 of 76800 pixels differ, each by 1/255, FLIP mean 0.00176 (the
  issue's threshold is 0.005). Rounding the colour toward zero to float16 between effects in the
  raw shader (``wgpu_intermediates=True``, post_chain.frag's F16_BETWEEN_STEPS) makes the two
  images bit-identical, which proves that this is the whole difference (round-to-nearest, GLSL's
  packHalf2x16, leaves 1854 pixels different: the rounding mode matters).
- Neighbourhood effects (fxaa, sharpen) and every repository scene: tests/test_vulkan_ref_neighbourhood.py.
- hdr = false: the intermediates are 8-bit sRGB, stored with lavapipe's approximate linear->sRGB
  encode; grayscale -> sepia -> srgb (rgba8unorm output), 160x120: 3954 pixels differ by 1/255,
  FLIP 0.0061. No shader formula reproduces the driver's encoder, so this one is bounded, not
  explained away.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from imagecheck import assert_close, assert_same_render, assert_within_tolerance

from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import load_png
from wgpurender.raw_path import render_reference
from wgpurender.raw_path.scene import render_scene_reference

REPO = Path(__file__).resolve().parent.parent
SCENES = REPO / "assets" / "scenes"
SIZE = (320, 240)
SMALL = (160, 120)
FLIP_THRESHOLD = 0.005  # the threshold for the lit final scene

pytestmark = pytest.mark.skipif(not (REPO / "assets" / "models" / "brick_torus.glb").is_file(),
                                reason="scene assets not present")


def scene_file(tmp_path: Path, name: str, text: str) -> Path:
    """A scene file in tmp_path; the asset paths ("../models/...") made absolute."""
    path = tmp_path / name
    path.write_text(text.replace('"../', f'"{REPO / "assets"}/'))
    return path


def without_post(text: str) -> str:
    return text.split("[[post]]")[0]


def keep_post(text: str, *effects: str) -> str:
    """The scene text with only the [[post]] entries of ``effects`` (in their order in the file)."""
    head, *entries = text.split("[[post]]")
    kept = [e for e in entries if e.split('effect = "')[1].split('"')[0] in effects]
    return head + "".join("[[post]]" + e for e in kept)


def wgpu_render(ctx, path: Path, size: tuple[int, int], **knobs) -> np.ndarray:
    """The wgpu path's image; ``knobs``: plan knobs, e.g. post_fuse=False for a pass (and a texture) per effect.

    The post path is pinned to fragment, the chain these exactness claims are about: on a discrete GPU the auto
    path is compute, which encodes sRGB in its shader (tests/test_post_paths.py compares the two paths).
    """
    from wgpurender.wgpu_path.scene import render_scene_file

    knobs.setdefault("post_path", "fragment")

    return render_scene_file(path, size=size, ctx=ctx, frames=1, knobs=knobs).pixels


def differing(a: np.ndarray, b: np.ndarray) -> int:
    return int((a.view(np.uint8).reshape(*a.shape[:2], -1) != b.view(np.uint8).reshape(*b.shape[:2], -1))
               .any(-1).sum())


@pytest.fixture(scope="module")
def final_pair(ctx):
    """(wgpu unfused: a pass and an rgba16float texture per effect, raw subpass) of final_subpass.toml."""
    path = SCENES / "final_subpass.toml"
    return wgpu_render(ctx, path, SIZE, post_fuse=False), render_scene_reference(path, size=SIZE)


# -- the lit final scene ---------------------------------------------------------------------------------------

def test_final_subpass_is_final_without_fxaa():
    """final_subpass.toml is final.toml with the fxaa [[post]] entry removed, nothing else changed."""
    from wgpurender.core.scene import load_scene

    final, subpass = load_scene(SCENES / "final.toml"), load_scene(SCENES / "final_subpass.toml")
    assert [s.effect for s in final.post] == ["tonemap", "fxaa", "vignette"]
    assert [(s.effect, s.params) for s in subpass.post] == [(s.effect, s.params) for s in final.post
                                                             if s.effect != "fxaa"]
    for field in ("camera", "models", "lights", "render", "materials"):
        assert getattr(final, field) == getattr(subpass, field), field


def test_final_scene_matches_wgpu(request, final_pair):
    """wgpu (pass per effect) vs raw (subpass 1, input attachment), lit final scene, tonemap -> vignette.

    FLIP mean <= 0.005 (the issue's threshold; measured 0.00176); tighter, as measured: no channel
    off by more than 1/255, at most 5% of the pixels differ (measured 3.5%: 2697 of 76800), all
    from float16 intermediates on the wgpu path (see the module docstring and the next test).
    """
    wgpu_pixels, raw = final_pair
    assert raw.shape == (SIZE[1], SIZE[0], 4) and raw.dtype == np.uint8
    assert (raw[..., :3].astype(int).sum(-1) > 60).mean() > 0.2  # the models are there, lit
    assert_close(request, raw, wgpu_pixels, max_abs=1, changed=0.05, flip_mean=FLIP_THRESHOLD)


def test_final_scene_exact_with_wgpus_intermediate_rounding(request, final_pair):
    """Rounding the chain's colour toward zero to float16 between effects, as lavapipe stores the wgpu
    path's rgba16float intermediates, makes the raw image identical to the wgpu image (threshold 0).

    This is the evidence for the cause of every difference in test_final_scene_matches_wgpu.
    """
    wgpu_pixels, _ = final_pair
    raw = render_scene_reference(SCENES / "final_subpass.toml", size=SIZE, wgpu_intermediates=True)
    assert_same_render(request, raw, wgpu_pixels, "raw and wgpu renders")


def test_fused_chain_equals_the_raw_subpass(request, ctx, final_pair):
    """The wgpu path's default, fused chain (tonemap + vignette in one pass, as functions in registers)
    composes the effects the way the raw subpass does: bit-identical to it (threshold 0; measured 0 pixels
    differ at 320x240 on lavapipe, where the unfused chain differs in 2697)."""
    _, raw = final_pair
    assert_same_render(request, raw, wgpu_render(ctx, SCENES / "final_subpass.toml", SIZE), "raw and fused wgpu")


@pytest.mark.parametrize("msaa", [1, 4])
def test_scene_subpass_is_exact(request, ctx, tmp_path, msaa):
    """The scene image alone (final.toml without post, rgba16float output): bit-identical float16, 1x and 4x.

    Same driver, sample positions, texture filtering, mip chains and float32 shading on both paths;
    the UBO bytes come from two independent std140 packers. Measured: 0 pixels differ.
    """
    text = without_post((SCENES / "final.toml").read_text())
    text = text.replace('output_format = "rgba8unorm-srgb"', 'output_format = "rgba16float"')
    text = text.replace("msaa = 4", f"msaa = {msaa}")
    path = scene_file(tmp_path, "final_hdr.toml", text)
    wgpu_pixels, raw = wgpu_render(ctx, path, SMALL), render_scene_reference(path, size=SMALL)
    assert raw.dtype == wgpu_pixels.dtype == np.float16
    assert np.isfinite(raw).all() and raw[..., :3].max() > 0.5
    assert_same_render(request, raw, wgpu_pixels, "raw and wgpu renders")


# -- the other scenes --------------------------------------------------------------------------------------------

def test_brick_without_fxaa_matches_wgpu(request, ctx, tmp_path):
    """brick.toml with its chain restricted to tonemap (fxaa removed), 160x120: exact (threshold 0).

    One effect: nothing is stored between effects, so nothing differs. Measured: 0 pixels.
    """
    path = scene_file(tmp_path, "brick.toml", keep_post((SCENES / "brick.toml").read_text(), "tonemap"))
    assert_same_render(request, render_scene_reference(path, size=SMALL), wgpu_render(ctx, path, SMALL))


def test_unlit_textured_scene_matches_wgpu(request, ctx, tmp_path):
    """An unlit textured scene (final.toml's models, albedo map only, unlit, hdr false, no post, msaa 4):
    one subpass straight into the sRGB output, exact (threshold 0). Measured: 0 pixels differ."""
    text = without_post((SCENES / "final.toml").read_text()).replace("hdr = true", "hdr = false")
    text = text.replace('albedo_map = "', 'unlit = true\nalbedo_map = "', 1)
    path = scene_file(tmp_path, "unlit_textured.toml", text)
    raw = render_scene_reference(path, size=SMALL)
    assert len(np.unique(raw[..., :3].reshape(-1, 3), axis=0)) > 500  # textured, not flat
    assert_same_render(request, raw, wgpu_render(ctx, path, SMALL))


def test_gltf_features_scene_matches_wgpu(request, ctx):
    """A model drawn with its own glTF materials (vertex colours, double-sided, alpha mask, per-texture samplers,
    several materials): both paths' images are the same bytes (measured on lavapipe: 0 of 76800 pixels differ)."""
    path = SCENES / "gltf_features.toml"
    assert_same_render(request, render_scene_reference(path, size=SIZE), wgpu_render(ctx, path, SIZE))


def test_unlit_scene_matches_wgpu(request, ctx):
    """unlit.toml (flat colour, msaa 1, no post): exact (threshold 0)."""
    path = SCENES / "unlit.toml"
    assert_same_render(request, render_scene_reference(path, size=SMALL), wgpu_render(ctx, path, SMALL))


def test_ldr_chain_with_shader_srgb(request, ctx, tmp_path):
    """hdr = false, grayscale -> sepia into rgba8unorm (the srgb step appended, encoding in the shader), 160x120.

    The scene image is rgba8unorm-srgb (subpassLoad decodes it like a texture read). Each effect
    alone is exact (grayscale alone into rgba8unorm-srgb: checked here); the chain differs by the wgpu path's 8-bit
    sRGB intermediates (lavapipe's approximate encoder). Measured: 3954 pixels off by 1/255, FLIP
    0.0061; bound: no channel off by more than 1/255, FLIP <= 0.01.
    """
    srgb_out = without_post((SCENES / "final.toml").read_text()).replace("hdr = true", "hdr = false")
    gray = '[[post]]\neffect = "grayscale"\namount = 0.5\n'
    one = scene_file(tmp_path, "gray.toml", srgb_out + gray)  # one step: the -srgb output encodes in hardware
    assert_same_render(request, render_scene_reference(one, size=SMALL), wgpu_render(ctx, one, SMALL))
    base = srgb_out.replace('output_format = "rgba8unorm-srgb"', 'output_format = "rgba8unorm"')
    two = scene_file(tmp_path, "gray_sepia.toml", base + gray + '[[post]]\neffect = "sepia"\namount = 0.7\n')
    assert_close(request, render_scene_reference(two, size=SMALL), wgpu_render(ctx, two, SMALL, post_fuse=False),
                 max_abs=1, flip_mean=0.01)


def test_glm_vulkan_scene_matches_wgpu(request, ctx, tmp_path):
    """retro.toml without sharpen (glm-vulkan camera, mirrored quad, reinhard -> sepia -> vignette -> srgb
    into rgba8unorm), 160x120: bit-identical with the wgpu path's float16 rounding between effects.

    The raw path uploads the tutorial's projection (GLM's Y flip kept) with a plain viewport, the wgpu
    path the corrected projection with its flipped viewport: the same pixels and winding. Measured:
    1349 pixels off by 1/255 without the rounding (FLIP 0.0032), 0 with it.
    """
    text = keep_post((SCENES / "retro.toml").read_text(), "tonemap", "sepia", "vignette", "srgb")
    path = scene_file(tmp_path, "retro.toml", text)
    wgpu_pixels = wgpu_render(ctx, path, SMALL, post_fuse=False)
    assert_same_render(request, render_scene_reference(path, size=SMALL, wgpu_intermediates=True), wgpu_pixels)
    assert_close(request, render_scene_reference(path, size=SMALL), wgpu_pixels, max_abs=1, flip_mean=FLIP_THRESHOLD)


# -- references ----------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["scene_final_subpass", "scene_unlit", "scene_gltf_features",
                                  "scene_metal_rough_spheres"])
def test_scene_references_are_current(request, name, raw_driver_class):
    """assets/reference/scene_*.png against a fresh raw render at 320x240, within the table's bounds
    (assets/reference/tolerances.toml, this driver class's row); written only by the raw path."""
    from wgpurender.raw_path.make_references import reference_path, render_named_reference

    path = reference_path(name)
    assert path.is_file(), f"{path} missing: run pytest --regenerate-references"
    fresh = render_named_reference(name)  # as make_references renders it: the scene's anisotropy (it says so)
    assert_within_tolerance(request, name, load_png(path), fresh, raw_driver_class)


def test_reference_command_renders_a_scene(tmp_path):
    """`wgpurender reference SCENE.toml -o ref.png --size WxH` writes the raw render."""
    from wgpurender.cli import main

    out = tmp_path / "ref.png"
    assert main(["reference", str(SCENES / "unlit.toml"), "-o", str(out), "--size", "64x48"]) == 0
    assert np.array_equal(load_png(out), render_reference(str(SCENES / "unlit.toml"), size=(64, 48)))


# -- refusals ------------------------------------------------------------------------------------------------------

def test_unsupported_output_format_is_refused():
    """bgra8unorm-srgb (a plan output format for swapchains): refused, naming the format."""
    with pytest.raises(UserError, match=r"output format bgra8unorm-srgb: the raw path renders only"):
        render_scene_reference(SCENES / "unlit.toml", size=(32, 24), fmt="bgra8unorm-srgb")


def test_every_problem_is_listed_at_once(tmp_path):
    """Too many effects and an unsupported output format: both named in one message. Neighbourhood effects
    (fxaa, sharpen) are no longer problems: they run in passes of their own (test_vulkan_ref_neighbourhood.py)."""
    from wgpurender.core.plan import resolve_plan
    from wgpurender.core.scene import load_scene
    from wgpurender.raw_path.device.uniforms import MAX_POST_STEPS
    from wgpurender.raw_path.scene import unsupported

    text = (SCENES / "final.toml").read_text() + '\n[[post]]\neffect = "sepia"\n' * MAX_POST_STEPS
    plan = resolve_plan(load_scene(scene_file(tmp_path, "long.toml", text)), None, output_format="bgra8unorm-srgb")
    problems = unsupported(plan)
    assert len(problems) == 2 and "post effects" in problems[0] and "bgra8unorm-srgb" in problems[1], problems
    assert unsupported(plan_of(SCENES / "final.toml")) == [] and unsupported(plan_of(SCENES / "retro.toml")) == []


def plan_of(path: Path):
    from wgpurender.core.plan import resolve_plan

    return resolve_plan(path, None)
