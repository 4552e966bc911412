"""The render plan: what is built for a scene, and, as important, what is not.

Each test writes a small scene (with its own tiny model and texture files in
tmp_path) and checks the plan's attachments, passes, variants and reasons.
No GPU is used: the plan is pure data.
"""

from __future__ import annotations

import dataclasses
import textwrap
from pathlib import Path

import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.plan import AdapterFacts, Knobs, explain_scene, main, resolve_knobs, resolve_plan
from wgpurender.core.scene import load_scene

REPO = Path(__file__).resolve().parent.parent
PNG_1X1 = bytes.fromhex(
    "89504e470d0a1a0a0000000d4948445200000001000000010806000000"
    "1f15c4890000000d49444154789c63f8cfc0f01f0005000201a5f2e1f30000000049454e44ae426082"
)

HEAD = """
[camera]
eye = [0, 1, 3]
target = [0, 0, 0]

[materials.brick]
albedo_map = "albedo.png"
normal_map = "normal.png"
roughness_map = "rough.png"

[materials.plain]
albedo_color = [0.5, 0.5, 0.5]

[materials.flat]
albedo_map = "albedo.png"
normal_map = "normal.png"
unlit = true
"""

SUN = '\n[[lights]]\ntype = "directional"\ndirection = [0, -1, 0]\n'
BULB = '\n[[lights]]\ntype = "point"\nposition = [0, 2, 0]\n'


def model(material: str) -> str:
    return f'\n[[models]]\npath = "tri.obj"\nmaterial = "{material}"\n'


def render(msaa: int = 4, hdr: bool = True, fmt: str = "rgba8unorm-srgb") -> str:
    return f'\n[render]\nsize = [64, 48]\nmsaa = {msaa}\nhdr = {str(hdr).lower()}\noutput_format = "{fmt}"\n'


def post(*effects: str) -> str:
    return "".join(f'\n[[post]]\neffect = "{e}"\n' for e in effects)


@pytest.fixture()
def make(tmp_path: Path):
    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    for name in ("albedo", "normal", "rough"):
        (tmp_path / f"{name}.png").write_bytes(PNG_1X1)

    def _make(body: str, **overrides):
        path = tmp_path / "scene.toml"
        path.write_text(textwrap.dedent(HEAD + body))
        return resolve_knobs(load_scene(path), overrides.pop("knobs", None) or Knobs(), **overrides)

    return _make


def names(plan) -> list[str]:
    return [a.name for a in plan.attachments]


def test_full_scene(make):
    plan = make(model("brick") + model("brick") + SUN + BULB + render(4, True) + post("tonemap", "fxaa"))
    assert names(plan) == ["msaa_color", "depth", "scene_color", "post_a", "fxaa_mask", "output"]
    msaa, depth, scene, temp, mask, out = plan.attachments
    assert (mask.format, mask.role) == ("depth16unorm", "post-mask")  # FXAA's edge mask is listed too
    assert (msaa.format, msaa.sample_count) == ("rgba16float", 4)
    assert (depth.format, depth.sample_count) == ("depth32float", 4)
    assert (scene.format, scene.sample_count) == ("rgba16float", 1)
    assert (out.format, out.size) == ("rgba8unorm-srgb", (64, 48))
    sp = plan.scene_pass
    assert (sp.color, sp.resolve_target, sp.depth) == ("msaa_color", "scene_color", "depth")
    assert [(p.effect, p.input, p.output) for p in plan.post_passes] == [
        ("tonemap", "scene_color", "post_a"), ("fxaa", "post_a", "output")]
    # both models share one material: one variant, one pipeline
    (variant,) = plan.variants
    assert variant.features == {"albedo_map", "normal_map", "roughness_map", "lighting",
                                "directional_lights:1", "point_lights:1"}
    assert variant.flags == {"albedo_map", "normal_map", "roughness_map", "lighting"}
    assert variant.count("point_lights") == 1 and variant.count("directional_lights") == 1
    assert variant.key == "albedo_map+directional_lights:1+lighting+normal_map+point_lights:1+roughness_map"
    assert variant.vertex_attributes == ("position", "normal", "uv", "tangent")
    (pipeline,) = plan.pipelines
    assert (pipeline.color_format, pipeline.sample_count, pipeline.depth_format) == ("rgba16float", 4, "depth32float")
    # the same mesh and material twice: one instanced draw of 2 (core/plan/batches.py)
    assert [(d.pipeline_key, d.instance_count) for d in sp.draws] == [(pipeline.key, 2)]
    assert [(pl.effects, pl.stage, pl.entry_point, pl.target_format, pl.depth_format)
            for pl in plan.post_pipelines] == [
        ("tonemap", "fragment", "fs_main", "rgba16float", None),
        ("fxaa", "fragment", "fs_mark", "rgba8unorm-srgb", "depth16unorm"),  # FXAA's second pipeline is listed
        ("fxaa", "fragment", "fs_main", "rgba8unorm-srgb", "depth16unorm")]
    assert {(t.path.name, t.format) for t in plan.textures} == {
        ("albedo.png", "rgba8unorm-srgb"), ("normal.png", "rgba8unorm"), ("rough.png", "rgba8unorm")}
    (sampler,) = plan.samplers
    assert sampler.spec.mipmap_filter == "linear"

    text = plan.explain()
    assert "normal_map: material 'brick' has normal_map = 'normal.png'" in text
    assert "lighting: material 'brick' is lit" in text
    assert "msaa_color: rgba16float, 64x48, 4 samples" in text
    assert "render.hdr = true" in text and "render.msaa = 4" in text
    assert "point_lights:1: material 'brick' is lit and the scene has 1 point light(s): lights[1]" in text


def test_unlit_scene_has_no_lighting(make):
    plan = make(model("plain").replace('"plain"', '{ albedo_color = [1, 0, 0], unlit = true }') + model("flat")
                + SUN + render(1, False))
    for v in plan.variants:
        assert "lighting" not in v.features
        assert not any(f.endswith(("_lights:1",)) for f in v.features)
        assert "normal" not in v.vertex_attributes and "tangent" not in v.vertex_attributes
        assert "normal_map" not in v.features
    assert {v.key for v in plan.variants} == {"base", "albedo_map"}
    assert any("normal_map ignored because unlit = true" in n for n in plan.notes)
    text = plan.explain()
    assert "      lighting:" not in text and "vertex attributes: position, uv\n" in text


def test_mixed_lit_and_unlit_materials_get_separate_variants(make):
    plan = make(model("brick") + model("flat") + BULB + render())
    brick, flat = (plan.variant(d.variant_key) for d in plan.scene_pass.draws)
    assert "lighting" in brick.features and "lighting" not in flat.features
    assert len(plan.pipelines) == 2


def test_msaa_1_has_no_multisampled_attachment_or_resolve(make):
    plan = make(model("brick") + SUN + render(msaa=1) + post("tonemap"))
    assert "msaa_color" not in names(plan)
    assert all(a.sample_count == 1 for a in plan.attachments)
    sp = plan.scene_pass
    assert (sp.color, sp.resolve_target) == ("scene_color", None)
    assert plan.pipelines[0].sample_count == 1
    assert "resolved" not in plan.explain()
    # the same scene with --msaa 4 on the command line
    plan4 = make(model("brick") + SUN + render(msaa=1) + post("tonemap"), msaa=4)
    assert plan4.attachment("msaa_color").sample_count == 4


def test_empty_chain_draws_straight_to_output(make):
    plan = make(model("brick") + SUN + render(msaa=4, hdr=False))
    assert plan.post_passes == () and plan.post_pipelines == ()
    assert names(plan) == ["msaa_color", "depth", "output"]
    assert plan.scene_pass.resolve_target == "output"
    assert plan.attachment("msaa_color").format == "rgba8unorm-srgb"  # resolve needs matching formats
    plan1 = make(model("brick") + SUN + render(msaa=1, hdr=False))
    assert names(plan1) == ["depth", "output"] and plan1.scene_pass.color == "output"
    assert "post pipelines: none" in plan1.explain()


def test_empty_chain_with_hdr_notes_the_unused_range(make):
    plan = make(model("plain") + render(msaa=1, hdr=True))
    assert "rgba16float" not in {a.format for a in plan.attachments}
    assert any("no post effect reads an HDR image" in n for n in plan.notes)


def test_no_normal_maps_no_tangents(make):
    plan = make(model("plain") + SUN + BULB + render() + post("fxaa"))
    assert "tangent" not in plan.vertex_attributes
    assert not any("normal_map" in f for f in plan.features)
    assert plan.vertex_attributes == {"position", "normal"}  # lit, but no texture: no uv either
    assert plan.textures == () and plan.samplers == ()


def test_no_hdr_target_without_hdr_or_tonemapping(make):
    plan = make(model("plain") + SUN + render(msaa=4, hdr=False) + post("fxaa", "sharpen", "vignette"))
    assert "rgba16float" not in {a.format for a in plan.attachments}
    assert plan.attachment("scene_color").format == "rgba8unorm-srgb"
    assert plan.attachment("post_a").format == "rgba8unorm-srgb"
    # tone mapping needs an HDR input even when hdr = false
    plan = make(model("plain") + SUN + render(msaa=1, hdr=False) + post("tonemap"))
    scene = plan.attachment("scene_color")
    assert scene.format == "rgba16float" and "tonemap maps HDR" in scene.reasons[0]


def test_plain_unorm_output_gets_explicit_encoding(make):
    plan = make(model("plain") + render(msaa=1, fmt="rgba8unorm") + post("tonemap"))
    assert [s.effect for s in plan.post_steps] == ["tonemap", "srgb"]
    assert "does not encode sRGB: an srgb step is appended" in plan.post_passes[-1].reason
    assert "srgb_output" not in plan.features
    # an explicit srgb last is not doubled; an -srgb output needs no pass
    plan = make(model("plain") + render(fmt="rgba8unorm") + post("tonemap", "srgb"))
    assert [s.effect for s in plan.post_steps] == ["tonemap", "srgb"]
    assert [p.effect for p in plan.post_passes] == ["tonemap+srgb"]  # fused: both per-pixel
    plan = make(model("plain") + render() + post("tonemap"))
    assert [p.effect for p in plan.post_passes] == ["tonemap"]
    # with no chain the scene shader encodes
    plan = make(model("plain") + render(fmt="rgba8unorm"))
    assert plan.post_passes == () and all("srgb_output" in v.flags for v in plan.variants)


def test_three_effects_ping_pong(make):
    plan = make(model("plain") + render() + post("tonemap", "sharpen", "vignette"), knobs=Knobs(post_fuse=False))
    assert [(p.input, p.output) for p in plan.post_passes] == [
        ("scene_color", "post_a"), ("post_a", "post_b"), ("post_b", "output")]
    assert names(plan).count("post_a") == 1 and "post_b" in names(plan)


def test_fusion_groups_per_pixel_effects_after_a_neighbourhood_one(make):
    """tonemap and grayscale read only their own pixel: one pass. sharpen reads neighbours, so it needs the
    finished image and starts a pass; vignette and sepia only need the pixel sharpen computed: same pass."""
    chain = ("tonemap", "grayscale", "sharpen", "vignette", "sepia")
    plan = make(model("plain") + render() + post(*chain))
    assert [p.effect for p in plan.post_passes] == ["tonemap+grayscale", "sharpen+vignette+sepia"]
    assert [s.effect for s in plan.post_steps] == list(chain)
    assert names(plan).count("post_a") == 1 and "post_b" not in names(plan)
    text = plan.explain()
    assert "fused: tonemap, grayscale each read only the pixel they write" in text
    assert "on the pixel sharpen just computed" in text
    assert "post_fuse: on <- render.post_fuse = true" in text
    unfused = plan.with_knobs(post_fuse=False)
    assert [p.effect for p in unfused.post_passes] == list(chain)
    assert "post_fuse: off <- knob post_fuse" in unfused.explain()


def test_fuse_can_be_switched_off_in_the_scene(make):
    plan = make(model("plain") + render() + "post_fuse = false\n" + post("tonemap", "vignette"))
    assert [p.effect for p in plan.post_passes] == ["tonemap", "vignette"]


def test_bytes_per_pass_are_the_compulsory_traffic(make):
    """Each texel read once and written once: 64x48 pixels, rgba16float 8 bytes, rgba8unorm-srgb 4 bytes."""
    plan = make(model("plain") + render(msaa=1) + post("tonemap", "vignette", "fxaa"))
    first, fxaa = plan.post_passes
    assert (first.bytes_read, first.bytes_written) == (64 * 48 * 8, 64 * 48 * 8)
    # FXAA on the fragment path also writes and depth-tests its depth16unorm mask (2 bytes a pixel)
    assert (fxaa.bytes_read, fxaa.bytes_written) == (64 * 48 * (8 + 2), 64 * 48 * (4 + 2))
    assert f"bytes: {64 * 48 * 16 / 1e6:.1f} MB read" in plan.explain()


def test_compute_path_writes_storage_formats_and_an_srgb_output_as_its_twin(make):
    """rgba8unorm-srgb cannot be a storage texture: offscreen, the output is made as its rgba8unorm twin,
    which the last compute pass writes directly (sRGB-encoded in the shader): no scratch, no copy; a
    swapchain image (output_storage off) is written through an rgba8unorm scratch copied into it. An 8-bit
    sRGB scene image's intermediates become rgba16float; no FXAA mask on the compute path."""
    scene = model("plain") + render(msaa=1, hdr=False) + post("fxaa", "sharpen")
    plan = make(scene, knobs=Knobs(post_path="compute"))
    assert [(p.path, p.output, p.output_format, p.copy_to, p.twin_of) for p in plan.post_passes] == [
        ("compute", "post_a", "rgba16float", None, None), ("compute", "output", "rgba8unorm", None, "rgba8unorm-srgb")]
    assert (plan.output_format, plan.target_format) == ("rgba8unorm-srgb", "rgba8unorm")
    assert not plan.has_attachment("post_scratch") and not plan.has_attachment("fxaa_mask")
    # the twin's bytes: 64x48 rgba16float read, 4 bytes a pixel written, nothing copied
    assert (plan.post_passes[-1].bytes_read, plan.post_passes[-1].bytes_written) == (64 * 48 * 8, 64 * 48 * 4)
    assert [(pl.stage, pl.entry_point) for pl in plan.post_pipelines] == [("compute", "cs_main")] * 2
    assert "rgba8unorm twin" in plan.explain() and "output: 64x48 rgba8unorm-srgb" in plan.explain()
    window = make(scene, knobs=Knobs(post_path="compute", output_storage=False))
    assert [(p.output, p.output_format, p.copy_to, p.twin_of) for p in window.post_passes][-1] == (
        "post_scratch", "rgba8unorm", "output", None)
    assert window.attachment("post_scratch").format == "rgba8unorm" and window.target_format == "rgba8unorm-srgb"
    # a plain rgba8unorm output is a storage format already: written directly, no twin
    plain = make(scene, output_format="rgba8unorm", knobs=Knobs(post_path="compute")).post_passes[-1]
    assert (plain.output, plain.twin_of, plain.copy_to) == ("output", None, None)
    # fragment path: the hardware encodes into the -srgb output itself
    assert make(scene, knobs=Knobs(post_path="fragment")).target_format == "rgba8unorm-srgb"
    # a bgra swapchain output cannot be written by a compute pass: the last pass stays a fragment pass
    plan = make(model("plain") + render(msaa=1) + post("tonemap"), output_format="bgra8unorm-srgb",
                knobs=Knobs(post_path="compute"))
    assert plan.post_passes[0].path == "fragment"
    # an rgba16float output is written directly, unless it is a swapchain image (not a storage texture)
    scene = model("plain") + render(msaa=1) + post("tonemap")
    direct = make(scene, output_format="rgba16float", knobs=Knobs(post_path="compute")).post_passes[0]
    assert (direct.output, direct.copy_to) == ("output", None)
    window = make(scene, output_format="rgba16float", knobs=Knobs(post_path="compute", output_storage=False))
    (p,) = window.post_passes
    assert (p.path, p.output, p.output_format, p.copy_to, p.copy_format) == (
        "compute", "post_scratch", "rgba16float", "output", "rgba16float")


def test_post_path_auto_rule(make):
    scene = model("plain") + render() + post("tonemap")
    assert make(scene).post_path == "fragment"  # adapter not known
    gpu = Knobs(adapter=AdapterFacts("DiscreteGPU", frozenset({"immediates"}), "H200"))
    cpu = Knobs(adapter=AdapterFacts("CPU", frozenset(), "llvmpipe"))
    assert make(scene, knobs=gpu).post_path == "compute" and make(scene, knobs=gpu).immediates is True
    assert make(scene, knobs=cpu).post_path == "fragment" and make(scene, knobs=cpu).immediates is False
    asked = model("plain") + render() + 'post_path = "compute"\n' + post("tonemap")
    assert make(asked, knobs=cpu).post_path == "compute"


def test_depth_knobs(make):
    plan = make(model("plain") + render(msaa=1)).with_knobs(depth_format="depth24plus", reverse_z=True)
    assert plan.attachment("depth").format == "depth24plus"
    assert (plan.pipelines[0].depth_format, plan.pipelines[0].depth_compare) == ("depth24plus", "greater")
    assert plan.scene_pass.depth_clear == 0.0
    assert "reverse_z: on" in plan.explain()
    with pytest.raises(UserError, match="plan knob post_path = 'vertex'"):
        plan.with_knobs(post_path="vertex")
    with pytest.raises(UserError, match="unknown plan knob 'gamma'"):
        plan.with_knobs(gamma=2.2)


def test_format_override_changes_output_only(make):
    plan = make(model("plain") + render() + post("tonemap"), output_format="rgba16float", size=(10, 20))
    assert plan.attachment("output").format == "rgba16float" and plan.size == (10, 20)
    assert "(overridden)" in plan.explain()
    with pytest.raises(UserError, match="unsupported output format"):
        make(model("plain"), output_format="rgb565")
    with pytest.raises(UserError, match="MSAA 8x is not supported"):
        make(model("plain"), msaa=8)
    with pytest.raises(UserError, match="scene_format knob needs a scene image"):
        make(model("plain"), knobs=Knobs(scene_format="rgba32float"))


def test_no_models_no_depth_no_pipelines(make):
    plan = make(render(msaa=1))
    assert names(plan) == ["output"] and plan.pipelines == () and plan.scene_pass.depth is None


def test_plan_is_pure_data(make):
    """No GPU object anywhere in the plan: every value is a dataclass, tuple, str, number, Path or SamplerSpec."""
    plan = make(model("brick") + model("flat") + SUN + render() + post("tonemap", "fxaa"))

    def walk(value):
        if dataclasses.is_dataclass(value):
            for f in dataclasses.fields(value):
                yield from walk(getattr(value, f.name))
        elif isinstance(value, (tuple, list, frozenset, set)):
            for v in value:
                yield from walk(v)
        else:
            yield value

    leaves = list(walk(plan))
    assert leaves and not [v for v in leaves if type(v).__module__.startswith("wgpu")]
    assert dataclasses.is_dataclass(plan) and type(plan).__dataclass_params__.frozen


def test_example_scenes_explain(capsys):
    scenes = sorted((REPO / "assets" / "scenes").glob("*.toml"))
    if not scenes or not (REPO / "assets" / "models" / "brick_torus.glb").is_file():
        pytest.skip("example scenes or assets not present")
    anchors = REPO.parent / "shared" / "anchors"
    needs_anchors = [p for p in scenes if "shared/anchors" in p.read_text() and not anchors.is_dir()]
    for path in scenes:
        if path not in needs_anchors:
            assert "passes:" in explain_scene(path)
    unlit = resolve_plan(REPO / "assets" / "scenes" / "unlit.toml", None)
    assert [v.key for v in unlit.variants] == ["base"] and unlit.post_passes == ()
    assert main([str(REPO / "assets" / "scenes" / "brick.toml")]) == 0
    assert "tonemap" in capsys.readouterr().out
    if needs_anchors:
        pytest.skip(f"{', '.join(p.name for p in needs_anchors)} not explained: they read the tutorial's model "
                    f"and texture from {anchors}, which is absent (the other scenes were checked)")


def test_main_reports_user_errors(tmp_path, capsys):
    assert main([str(tmp_path / "missing.toml")]) == 2
    assert "scene file not found" in capsys.readouterr().err
