"""The knob post_intermediate: what an 8-bit image between post passes costs in accuracy, against float64.

The chain is final.toml's (tonemap, FXAA, vignette) over the coloured test image of tests/test_fxaa_reference.py
(drawn 1:1, unlit, nearest, into the rgba16float scene image, so the test knows the scene image exactly). The
truth is float64 throughout, written in the tests (test_post.ref_aces, fxaa_reference.fxaa, test_post.ref_vignette),
nothing imported from the renderer: no rounding between the effects, the sRGB curve at the end. Each setting is
drawn on the wgpu path (fragment and compute) and on the raw path, and judged in 8-bit sRGB steps against the
truth's round(255 * encoded).

What "auto" (rgba16float between the passes, today's image) costs is the calibration; rgba8unorm stores the
tone-mapped values linear in 8 bits, whose steps are coarse in the darks, so its error is larger there;
rgba8unorm-srgb stores them sRGB-encoded (steps even to the eye) and the sampler decodes before it filters; none
stores nothing: one pass recomputes tonemap for every texel FXAA reads, its bilinear taps computed in the shader.

Measured 2026-11-27 at 96x72 pixels, error in 8-bit steps against the truth (max, mean, share of pixels off by
more than 1) over the three ways (benchmarks/post_intermediate_error.py; docs/perf-lavapipe/2026-11-27-post/ and
docs/perf-h100/2026-11-27-post/):

| setting | lavapipe max / mean / share > 1 | H100 max / mean / share > 1 |
|---|---|---|
| auto (rgba16float) | 10 / 0.13-0.16 / 0.043% (FXAA's edge test flips) | 2 / 0.08-0.14 / 0.029% |
| rgba8unorm | 7 / 0.74-0.76 / 27.2-27.6% | 10 / 0.71-0.72 / 22.1-22.4% |
| rgba8unorm-srgb | 1 / 0.20-0.24 / 0 | 7 / 0.20-0.29 / 2.1-2.2% |
| none (wgpu only) | 1 / 0.13-0.16 / 0 | 1 / 0.08-0.13 / 0 |

So the calibrated tolerance (auto's, with margin: AUTO_MAX, AUTO_OVER1) holds none on both machines,
rgba8unorm-srgb only on lavapipe, rgba8unorm nowhere. The default stays "auto" (today's image): none is slower
on both machines (bench post-roofline) and the raw path cannot draw it.
"""

from __future__ import annotations

import numpy as np
import pytest
from fxaa_reference import fxaa
from shading_model import srgb_decode, srgb_encode
from test_fxaa_reference import H, W, coloured_image, quad_scene
from test_post import ref_aces, ref_vignette

from wgpurender.core.errors import UserError
from wgpurender.core.plan import resolve_plan
from wgpurender.core.scene import load_scene

EXPOSURE, STRENGTH, RADIUS, SOFTNESS = 1.6, 0.45, 0.55, 0.5
KNOBS = ("auto", "rgba8unorm", "rgba8unorm-srgb", "none")
WAYS = {"auto": ("fragment", "compute", "raw"), "rgba8unorm": ("fragment", "compute", "raw"),
        "rgba8unorm-srgb": ("fragment", "compute", "raw"), "none": ("fragment", "compute")}  # raw refuses none
AUTO_MAX, AUTO_OVER1 = 16, 0.002  # measured 10 and 0.043% (3 of 6912 pixels); ~14 pixels allowed
EIGHT_MAX, EIGHT_OVER1 = 14, 0.35  # rgba8unorm: measured 7 and 27.6% (lavapipe), 10 and 22.4% (H100)
ENC_MAX, ENC_OVER1 = 10, 0.03  # rgba8unorm-srgb: measured 1 and 0% (lavapipe), 7 and 2.2% (H100)


def write_scene(folder):
    path = folder / "scene.toml"
    path.write_text(quad_scene(folder, coloured_image(), "rgba8unorm-srgb", f"""[[post]]
effect = "tonemap"
exposure = {EXPOSURE}

[[post]]
effect = "fxaa"

[[post]]
effect = "vignette"
strength = {STRENGTH}
radius = {RADIUS}
softness = {SOFTNESS}
"""), encoding="utf-8")
    return path


def truth() -> np.ndarray:
    """The chain in float64 on the exact scene image, as 8-bit sRGB values (float, unrounded)."""
    scene_image = np.ones((H, W, 4))
    scene_image[..., :3] = srgb_decode(coloured_image()[..., :3] / 255.0).astype(np.float16)
    out = ref_vignette(fxaa(ref_aces(scene_image, EXPOSURE)), STRENGTH, RADIUS, SOFTNESS)
    return srgb_encode(out[..., :3]) * 255.0


def render(ctx, path, way: str, intermediate: str) -> np.ndarray:
    if way == "raw":
        from wgpurender.raw_path.device.context import get_vulkan
        from wgpurender.raw_path.scene.frame import render_scene_plan

        return render_scene_plan(resolve_plan(path, get_vulkan().adapter_facts(),
                                              post_intermediate=intermediate)).astype(np.float64)
    from wgpurender.wgpu_path.scene import render_plan

    plan = resolve_plan(path, ctx.adapter_facts(), post_path=way, post_intermediate=intermediate)
    return render_plan(ctx, plan, frames=1).pixels.astype(np.float64)


def errors(got: np.ndarray, want: np.ndarray) -> dict[str, float]:
    err = np.abs(got[..., :3] - np.round(want))
    return {"max": float(err.max()), "mean": float(err.mean()), "over1": float((err.max(-1) > 1).mean())}


@pytest.fixture(scope="module")
def measured(ctx, tmp_path_factory):
    path = write_scene(tmp_path_factory.mktemp("post-intermediate"))
    want = truth()
    return {(way, knob): render(ctx, path, way, knob) for knob in KNOBS for way in WAYS[knob]}, want, path


def test_the_knob_stores_the_intermediate_it_names(measured):
    _, _, path = measured
    scene = load_scene(path)
    for way in ("fragment", "compute"):
        auto = resolve_plan(scene, None, post_path=way)
        eight = resolve_plan(scene, None, post_path=way, post_intermediate="rgba8unorm")
        assert auto.attachment("post_a").format == "rgba16float" and eight.attachment("post_a").format == "rgba8unorm"
        assert eight.setting("post_intermediate") == "rgba8unorm" and "8 bits" in eight.explain()
        # half the bytes between the passes: tonemap writes 4 bytes a pixel instead of 8, FXAA reads 4
        assert auto.post_passes[0].bytes_written - eight.post_passes[0].bytes_written == W * H * 4
        assert auto.post_passes[1].bytes_read - eight.post_passes[1].bytes_read == W * H * 4
        encoded = resolve_plan(scene, None, post_path=way, post_intermediate="rgba8unorm-srgb")
        assert encoded.attachment("post_a").format == "rgba8unorm-srgb"
    # an -srgb intermediate is no storage texture: on the compute path tonemap writes an rgba8unorm scratch
    # (sRGB-encoded in the shader) copied into post_a, which FXAA samples (decoded before filtering)
    first = resolve_plan(scene, None, post_path="compute", post_intermediate="rgba8unorm-srgb").post_passes[0]
    assert (first.output, first.output_format, first.copy_to, first.copy_format) == (
        "post_scratch", "rgba8unorm", "post_a", "rgba8unorm-srgb")


@pytest.mark.parametrize("way", ["fragment", "compute", "raw"])
def test_each_setting_against_the_float64_chain(measured, way):
    images, want, _ = measured
    auto, eight = errors(images[(way, "auto")], want), errors(images[(way, "rgba8unorm")], want)
    encoded = errors(images[(way, "rgba8unorm-srgb")], want)
    assert auto["max"] <= AUTO_MAX and auto["over1"] <= AUTO_OVER1, f"{way} auto: {auto}"
    assert eight["max"] <= EIGHT_MAX and eight["over1"] <= EIGHT_OVER1, f"{way} rgba8unorm: {eight}"
    # linear 8 bits is a real cost, far outside the tolerance; sRGB-encoded 8 bits is inside it on lavapipe but
    # not on the H100 (2.2% of pixels over one step there), so it is held to its own measured bound
    assert eight["over1"] > AUTO_OVER1 and eight["mean"] > 3 * auto["mean"], f"{way}: {eight} vs {auto}"
    assert encoded["max"] <= ENC_MAX and encoded["over1"] <= ENC_OVER1, f"{way} rgba8unorm-srgb: {encoded}"
    assert encoded["mean"] < eight["mean"] / 2, f"{way}: sRGB-encoded {encoded} vs linear {eight}"
    for knob in KNOBS[1:]:
        if way in WAYS[knob]:
            assert not np.array_equal(images[(way, "auto")], images[(way, knob)]), f"{way} {knob} changed nothing"


@pytest.mark.parametrize("way", ["fragment", "compute"])
def test_recomputing_instead_of_storing_is_within_the_tolerance(measured, way):
    """post_intermediate = none: one pass, tonemap applied to every texel FXAA reads and its bilinear taps
    computed in the shader. Nothing is rounded between the effects, so the error is at most auto's (measured:
    max 1 step, none over 1, mean 0.13-0.16 like auto's)."""
    images, want, _ = measured
    auto, none = errors(images[(way, "auto")], want), errors(images[(way, "none")], want)
    assert none["max"] <= AUTO_MAX and none["over1"] <= AUTO_OVER1, f"{way} none: {none}"
    assert none["mean"] <= auto["mean"] * 1.1, f"{way}: none {none} vs auto {auto}"


def test_recomputing_plans_one_pass_and_the_raw_path_refuses_it(measured):
    _, _, path = measured
    scene = load_scene(path)
    for way in ("fragment", "compute"):
        plan = resolve_plan(scene, None, post_path=way, post_intermediate="none")
        (p,) = plan.post_passes
        assert (p.effect, p.prelude, p.input, p.output) == ("tonemap+fxaa+vignette", 1, "scene_color", "output")
        assert not plan.has_attachment("post_a") and not plan.has_attachment("fxaa_mask")
        assert (p.bytes_read, p.bytes_written) == (W * H * 8, W * H * 4)  # the HDR scene image in, 8-bit sRGB out
        assert "tonemap recomputed for every texel fxaa reads" in plan.explain()
    from wgpurender.raw_path.scene.support import unsupported

    assert any("post_intermediate = 'none'" in u for u in unsupported(resolve_plan(scene, None,
                                                                                  post_intermediate="none")))
    no_fxaa = scene.__class__(**{**scene.__dict__, "post": (scene.post[0], scene.post[2])})
    with pytest.raises(UserError, match="no per-pixel effect comes before an FXAA pass"):
        resolve_plan(no_fxaa, None, post_intermediate="none", post_fuse=False)


def test_raw_and_wgpu_store_the_same_intermediate(measured):
    """The raw path's handoff image takes the knob's format too: per setting, raw equals wgpu's fragment path
    within 1/255 (the float32 between fused effects on one side, lavapipe's sRGB encoder on the other). The
    compute path encodes an -srgb intermediate in its shader, the fragment path in lavapipe's (approximate)
    encoder: one step apart there, two after the output's own encoding (measured: 10 of 6912 pixels)."""
    images, _, _ = measured
    for knob in KNOBS[:3]:
        assert np.abs(images[("raw", knob)] - images[("fragment", knob)]).max() <= 1, knob
        diff = np.abs(images[("compute", knob)] - images[("fragment", knob)]).max(-1)
        bound = 2 if knob.endswith("srgb") else 1
        assert diff.max() <= bound and (diff > 1).mean() <= 0.005, (knob, diff.max(), (diff > 1).sum())


def test_a_chain_with_nothing_between_passes_refuses_the_knob(measured):
    _, _, path = measured
    scene = load_scene(path)
    with pytest.raises(UserError, match="stores no image between passes"):
        resolve_plan(scene.__class__(**{**scene.__dict__, "post": scene.post[:1]}), None,
                     post_intermediate="rgba8unorm")
    with pytest.raises(UserError, match="post_intermediate = 'rgba32float': choose one of auto, rgba16float, rgba8"):
        resolve_plan(scene, None, post_intermediate="rgba32float")


def test_the_raw_path_stores_the_knob_at_the_handoff_and_the_scene_format_inside_fxaa(measured, monkeypatch):
    """The raw images made for the chain (tonemap | FXAA + vignette): the handoff FXAA samples takes the knob's
    format, like the wgpu path's intermediate; the tail's input attachment (FXAA's result, read by vignette in
    the same render pass) keeps the scene image's format, as the wgpu path's fused pass keeps float32 there."""
    from wgpurender.raw_path.post import neighbourhood
    from wgpurender.raw_path.scene import frame

    _, _, path = measured
    made = []

    def spy(module):
        real = module.create_image

        def create_image(ctx, owned, size, fmt, usage, *args, **kwargs):
            made.append((module.__name__.rsplit(".", 1)[-1], fmt, usage))
            return real(ctx, owned, size, fmt, usage, *args, **kwargs)
        monkeypatch.setattr(module, "create_image", create_image)

    spy(neighbourhood)
    spy(frame)
    render(None, path, "raw", "rgba8unorm")
    assert ("frame", "rgba8unorm", frame.USAGES["handoff"]) in made
    assert [m for m in made if m[0] == "neighbourhood"] == [
        ("neighbourhood", "rgba16float", neighbourhood.TAIL_INPUT_USAGE)]
