"""The scene renderer draws what the plan lists, and nothing else.

Small images (160x120 and less) so the file runs in seconds on lavapipe. Exact comparisons
(``array_equal``) where the same arithmetic must give the same bytes; stated tolerances otherwise.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wgpurender.cli import main
from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import save_png
from wgpurender.core.models import procedural
from wgpurender.core.plan import resolve_plan
from wgpurender.core.scene import parse_scene
from wgpurender.wgpu_path.device.targets import read_texture
from wgpurender.wgpu_path.scene import SceneRenderer, render_frame, render_scene_file, shader_source

ROOT = Path(__file__).resolve().parents[1]
ASSETS = ROOT / "assets"
FINAL = ASSETS / "scenes" / "final.toml"
CUBE = ASSETS / "models" / "brick_cube.obj"
TORUS = ASSETS / "models" / "brick_torus.glb"
ALBEDO = ASSETS / "textures" / "brick_albedo.png"
NORMAL = ASSETS / "textures" / "brick_normal.png"
SMALL = (160, 120)

LIT_CUBE = f"""
[camera]
eye = [2.0, 1.6, 2.6]
target = [0.0, 0.0, 0.0]

[[models]]
path = "{CUBE}"
material = {{ albedo_color = [0.8, 0.5, 0.3] }}

[[lights]]
type = "directional"
direction = [-0.3, -1.0, -0.5]

[render]
size = [160, 120]
hdr = false
clear_color = [0.0, 0.0, 0.0, 1.0]
"""


def _renderer(ctx, text: str, folder: Path, **overrides) -> SceneRenderer:
    scene = parse_scene(text, folder / "scene.toml")
    return SceneRenderer(ctx, scene, resolve_plan(scene, None, **overrides))


def _render(ctx, renderer: SceneRenderer) -> np.ndarray:
    target = renderer.create_output()
    return render_frame(ctx, renderer, target)[0]


# -- the final scene --------------------------------------------------------------------------


def test_final_scene_renders_finite_and_covers_the_frame(ctx):
    """Float output (rgba16float, linear): every value finite; >= 25% of pixels brighter than the
    background (the torus and cube fill about 40% of the frame); both brick colours present."""
    result = render_scene_file(FINAL, size=SMALL, fmt="rgba16float", ctx=ctx, frames=1)
    pixels = result.pixels.astype(np.float32)
    assert pixels.shape == (120, 160, 4)
    assert np.all(np.isfinite(pixels))
    lit = pixels[..., :3].max(axis=-1) > 0.05
    assert lit.mean() >= 0.25, lit.mean()
    reddish = (pixels[..., 0] > 1.4 * pixels[..., 2]) & lit
    assert reddish.mean() > 0.05  # brick albedo came through the sRGB texture and the lighting


def test_final_scene_plan_is_what_gets_built(ctx):
    """The fragment chain, pinned: on a discrete GPU the auto post path is compute, which needs no FXAA mask
    (tests/test_plan_is_what_is_built.py checks both paths against what is created)."""
    scene, plan = _scene_and_plan(FINAL, size=SMALL)
    renderer = SceneRenderer(ctx, scene, plan.with_knobs(post_path="fragment"))
    _render(ctx, renderer)
    plan = renderer.plan
    assert set(renderer.attachments) == {"msaa_color", "depth", "scene_color", "post_a", "fxaa_mask"}
    assert renderer.attachments["msaa_color"].sample_count == 4
    assert renderer.attachments["scene_color"].format == "rgba16float"
    assert renderer.attachments["fxaa_mask"].format == "depth16unorm"
    assert [p.effect for p in plan.post_passes] == ["tonemap", "fxaa+vignette"]  # vignette fused into fxaa's pass
    assert [s.effect for s in plan.post_steps] == ["tonemap", "fxaa", "vignette"]
    assert len(renderer.scene_pass.pipelines) == len(plan.pipelines) == len(plan.variants) == 1


def _scene_and_plan(path, **overrides):
    from wgpurender.core.scene import load_scene

    scene = load_scene(path)
    return scene, resolve_plan(scene, None, **overrides)


# -- post chain and MSAA ----------------------------------------------------------------------


def test_empty_post_chain_draws_the_same_image_as_the_chain_reads(ctx, tmp_path):
    """Without [[post]] the scene draws straight into an rgba16float output; with a chain it draws
    into scene_color, which the chain reads. Both must hold the same bytes (exact)."""
    base = LIT_CUBE.replace("hdr = false", "hdr = true") + '\noutput_format = "rgba16float"\n'
    plain = _renderer(ctx, base, tmp_path)
    chained = _renderer(ctx, base + '\n[[post]]\neffect = "tonemap"\n', tmp_path)
    assert plain.plan.post_passes == () and plain.plan.scene_pass.writes == "output"
    assert len(plain.chain) == 0
    direct = _render(ctx, plain)
    _render(ctx, chained)
    scene_color = read_texture(ctx, chained.attachments["scene_color"])
    assert np.array_equal(direct, scene_color)
    assert np.count_nonzero(direct[..., :3].max(axis=-1) > 0) > 0.1 * direct.shape[0] * direct.shape[1]


def test_msaa_changes_only_edges(ctx, tmp_path):
    """A flat-coloured lit cube: msaa 1 has no resolve (plan and attachments); msaa 4 differs from
    it by more than 1/255 only within 1 pixel of an edge (a pixel whose 3x3 neighbourhood in the
    msaa-1 image varies by more than 8/255), and does differ somewhere (it anti-aliases)."""
    one = _renderer(ctx, LIT_CUBE, tmp_path, msaa=1)
    four = _renderer(ctx, LIT_CUBE, tmp_path, msaa=4)
    assert one.plan.scene_pass.resolve_target is None and not one.plan.has_attachment("msaa_color")
    assert four.plan.scene_pass.resolve_target == "output"
    a = _render(ctx, one)[..., :3].astype(np.int32)
    b = _render(ctx, four)[..., :3].astype(np.int32)
    assert "msaa_color" not in one.attachments
    h, w = a.shape[:2]
    padded = np.pad(a, ((1, 1), (1, 1), (0, 0)), mode="edge")
    neighbours = np.stack([padded[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)])
    edges = (neighbours.max(axis=0) - neighbours.min(axis=0)).max(axis=-1) > 8
    changed = np.abs(a - b).max(axis=-1) > 1
    assert changed.any()
    assert not np.any(changed & ~edges), np.argwhere(changed & ~edges)[:5]


# -- shader variants ----------------------------------------------------------------------------


def _code(wgsl: str) -> str:
    """WGSL without its comment lines (the header describes every variant, so it names everything)."""
    return "\n".join(line for line in wgsl.splitlines() if not line.strip().startswith("//"))


def _plain_quad(tmp_path: Path, aspect: float) -> Path:
    return procedural.write_obj(tmp_path / "quad.obj", procedural.plane(width=2.0 * aspect, height=2.0))


def test_unlit_shader_has_no_lighting_code_and_renders_the_texel(ctx, tmp_path):
    """A quad exactly filling a 64x48 view, unlit, nearest filter, one mip level, with a random 64x48
    texture: every output byte equals the texel's byte (sRGB decode on sampling, encode on write)."""
    w, h = 64, 48
    rng = np.random.default_rng(3)
    texels = rng.integers(0, 256, size=(h, w, 4), dtype=np.uint8)
    texels[..., 3] = 255
    save_png(tmp_path / "albedo.png", texels)
    quad = _plain_quad(tmp_path, w / h)
    distance = 1.0 / np.tan(np.radians(45.0) / 2.0)  # the quad's half-height 1 fills fov_y 45
    text = f"""
[camera]
eye = [0.0, 0.0, {float(distance)!r}]
target = [0.0, 0.0, 0.0]

[[models]]
path = "{quad}"

[models.material]
albedo_map = "albedo.png"
unlit = true
sampler = {{ filter = "nearest", mipmaps = false, address_mode = "clamp-to-edge" }}

[render]
size = [{w}, {h}]
msaa = 1
hdr = false
"""
    renderer = _renderer(ctx, text, tmp_path)
    (variant,) = renderer.plan.variants
    code = _code(shader_source(variant, ctx.has("immediates")))
    for word in ("light", "shade", "normal", "blinn_phong", "tangent", "roughness", "DirectionalLight"):
        assert word not in code, word
    assert variant.vertex_attributes == ("position", "uv")
    pixels = _render(ctx, renderer)
    assert np.array_equal(pixels[..., :3], texels[..., :3])


def test_variant_without_normal_map_has_no_tangent_attribute(ctx, tmp_path):
    text = LIT_CUBE.replace("material = { albedo_color = [0.8, 0.5, 0.3] }",
                            f'material = {{ albedo_map = "{ALBEDO}" }}')
    renderer = _renderer(ctx, text, tmp_path)
    (variant,) = renderer.plan.variants
    assert variant.vertex_attributes == ("position", "normal", "uv")
    source = _code(shader_source(variant, ctx.has("immediates")))
    assert "tangent" not in source and "@location(3)" not in source and "var normal_tex" not in source
    from wgpurender.wgpu_path.scene.shader_interface import vertex_layout

    layout = vertex_layout(variant)
    assert layout["array_stride"] == 4 * (3 + 3 + 2)
    assert [a["shader_location"] for a in layout["attributes"]] == [0, 1, 2]
    assert np.isfinite(_render(ctx, renderer).astype(np.float32)).all()


def test_models_with_the_same_features_share_one_pipeline(ctx, tmp_path):
    """Two different materials with the same features (albedo + normal map, lit) and a third, flat one."""
    text = f"""
[camera]
eye = [0.0, 1.0, 5.0]
target = [0.0, 0.0, 0.0]

[materials.a]
albedo_map = "{ALBEDO}"
normal_map = "{NORMAL}"

[materials.b]
albedo_map = "{ALBEDO}"
normal_map = "{NORMAL}"
albedo_color = [0.5, 0.9, 0.5]

[[models]]
path = "{CUBE}"
material = "a"
transform = {{ translate = [-1.5, 0, 0] }}

[[models]]
path = "{TORUS}"
material = "b"

[[models]]
path = "{CUBE}"
transform = {{ translate = [1.5, 0, 0] }}

[[lights]]
type = "directional"
direction = [0, -1, -1]

[render]
size = [96, 64]
msaa = 1
"""
    renderer = _renderer(ctx, text, tmp_path)
    _render(ctx, renderer)
    pipelines = renderer.scene_pass.pipelines
    assert len(pipelines) == 2
    used = [state[1] for state in renderer.scene_pass.draw_state]
    assert used[0] is used[1] and used[2] is not used[0]


def test_immediates_and_uniform_fallback_give_the_same_image(ctx, tmp_path):
    if not ctx.has("immediates"):
        pytest.skip("adapter has no immediates: only the fallback can run")
    scene = parse_scene(LIT_CUBE, tmp_path / "scene.toml")
    plan = resolve_plan(scene, None)
    with_immediates = _render(ctx, SceneRenderer(ctx, scene, plan.with_knobs(immediates="on")))
    fallback_renderer = SceneRenderer(ctx, scene, plan.with_knobs(immediates="off"))
    assert "immediates: off <- knob immediates" in fallback_renderer.plan.explain()
    assert fallback_renderer.scene_pass.material_buffer is not None
    assert np.array_equal(with_immediates, _render(ctx, fallback_renderer))


# -- bad input ------------------------------------------------------------------------------------


def test_nan_positions_are_a_user_error(ctx, tmp_path):
    (tmp_path / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")
    text = LIT_CUBE.replace(str(CUBE), "bad.obj")
    with pytest.raises(UserError, match="NaN or infinite"):
        _renderer(ctx, text, tmp_path)


def test_more_lights_than_the_limit_is_a_user_error(ctx, tmp_path):
    from wgpurender.core.scene import MAX_LIGHTS

    lights = '\n[[lights]]\ntype = "point"\nposition = [0, 1, 0]\n' * (MAX_LIGHTS + 1)
    (tmp_path / "scene.toml").write_text(LIT_CUBE + lights)
    with pytest.raises(UserError, match=f"at most MAX_LIGHTS = {MAX_LIGHTS}"):
        render_scene_file(tmp_path / "scene.toml", ctx=ctx)


def test_missing_texture_fails_in_the_cli_with_one_line(capsys, tmp_path):
    scene = tmp_path / "scenes" / "s.toml"
    scene.parent.mkdir()
    scene.write_text(LIT_CUBE.replace("material = { albedo_color = [0.8, 0.5, 0.3] }",
                                      'material = { albedo_map = "../textures/nope.png" }'))
    out = tmp_path / "out.png"
    code = main(["render", str(scene), "-o", str(out)])
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == 2 and len(lines) == 1 and "Traceback" not in err
    assert "nope.png" in lines[0] and "not found" in lines[0] and str(tmp_path / "textures") in lines[0]
    assert not out.exists()


def test_explain_prints_the_plan_without_rendering(capsys, tmp_path):
    code = main(["render", str(FINAL), "--explain", "--size", "64x48"])
    out = capsys.readouterr().out
    assert code == 0
    assert "output: 64x48 rgba8unorm-srgb, msaa 4" in out and "+ vignette(strength=0.45" in out
    if "post_path: compute" in out:  # the auto rule on a discrete GPU: one dispatch, no FXAA mask, no copy
        assert "fxaa+vignette compute cs_main" in out and "fxaa_mask" not in out and "post_scratch" not in out
        assert "output: rgba8unorm, 64x48" in out and "its storage twin rgba8unorm" in out
    else:
        assert "fxaa_mask: depth16unorm" in out and "fxaa+vignette fragment fs_mark" in out
