"""Every repository scene on the raw-Vulkan path against the wgpu path, neighbourhood effects included.

The raw path runs the per-pixel post effects in an input-attachment subpass and each neighbourhood
effect (fxaa, sharpen) in a render pass of its own that samples the previous result after an
explicit image barrier (wgpurender/raw_path/post/neighbourhood.py); its FXAA and sharpen are
GLSL written as the same algorithm as shaders_wgsl/post_fxaa.wgsl and post_sharpen.wgsl. Both
paths run on lavapipe in this process, so exact equality is the expectation wherever the
arithmetic is the same.

The one known difference (tests/test_vulkan_ref_scene.py explains it): several per-pixel effects
in one subpass keep float32 between them, where the wgpu path stores each effect's result in an
rgba16float texture, which lavapipe rounds toward zero. Measured at 160x120 (lavapipe, Mesa 22.3.6,
AMD EPYC, 2026-11-23):

| scene | chain (| = a cut before a neighbourhood pass) | pixels differing | with wgpu's float16 rounding |
|---|---|---|---|
| brick | tonemap | fxaa | 0 | 0 |
| final | tonemap | fxaa, vignette | 0 | 0 |
| final_subpass | tonemap, vignette | 512, max 1/255, FLIP 0.0016 | 0 |
| retro | tonemap, sepia, vignette | sharpen, srgb | 1415, max 1/255, FLIP 0.0029 | 0 |
| unlit, vulkan_tutorial_28/30 | no chain | 0 | 0 |

So: exact for every scene with ``wgpu_intermediates=True`` (threshold 0) against the wgpu path's
unfused chain (``post_fuse = false``: a pass and an rgba16float texture per effect).

The wgpu path's default, fused chain composes per-pixel effects in registers like the subpass, and also
runs the per-pixel effects after a neighbourhood effect in that effect's pass, where the raw path stores
the neighbourhood result in an image and reads it in its next subpass. Fused wgpu against the raw path
as it renders by default, same run (plan engineer, 2026-11-23): brick, final_subpass, unlit 0 pixels;
final (fxaa, vignette) 391 and retro (sharpen, srgb) 561 of 19200, each by 1/255: exact unless a
neighbourhood effect is followed by a per-pixel one, else max 1/255 and FLIP <= 0.005.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.plan import resolve_plan
from wgpurender.core.verdict.compare import compare_images
from wgpurender.raw_path.post.neighbourhood import split_chain
from wgpurender.raw_path.scene import render_scene_reference

REPO = Path(__file__).resolve().parent.parent
SCENES = REPO / "assets" / "scenes"
ANCHORS = REPO.parent / "shared" / "anchors" / "vulkan-tutorial"
SIZE = (160, 120)
FLIP_THRESHOLD = 0.005
ALL_SCENES = sorted(p.name for p in SCENES.glob("*.toml"))
PIXEL_EFFECTS = {"tonemap", "vignette", "grayscale", "sepia", "srgb"}

pytestmark = pytest.mark.skipif(not (REPO / "assets" / "models" / "brick_torus.glb").is_file(),
                                reason="scene assets not present")


def needs_anchors(name: str) -> bool:
    return name.startswith("vulkan_tutorial")


def scene_path(name: str) -> Path:
    if needs_anchors(name) and not ANCHORS.is_dir():
        pytest.skip("../shared/anchors/vulkan-tutorial not present (the tutorial's model and texture)")
    return SCENES / name


def differing(a: np.ndarray, b: np.ndarray) -> int:
    return int((a.view(np.uint8).reshape(*a.shape[:2], -1) != b.view(np.uint8).reshape(*b.shape[:2], -1))
               .any(-1).sum())


def neighbourhood_then_pixel(effects: list[str]) -> bool:
    """True when a neighbourhood effect's result is stored by the raw path but kept in registers by the fused
    wgpu path (the per-pixel effect after it runs in the same wgpu pass)."""
    return any(a not in PIXEL_EFFECTS and b in PIXEL_EFFECTS for a, b in zip(effects, effects[1:], strict=False))


@pytest.fixture(scope="module")
def wgpu_images(ctx):
    from wgpurender.wgpu_path.scene import render_scene_file

    cache = {}

    def get(name: str, fuse: bool = True) -> np.ndarray:
        """The wgpu path's fragment chain (the raw path's twin; auto picks compute on a discrete GPU, compared in
        test_post_paths), fused (its default) or unfused (a pass and a float16 texture per effect)."""
        if (name, fuse) not in cache:
            cache[(name, fuse)] = render_scene_file(scene_path(name), size=SIZE, ctx=ctx, frames=1,
                                                    knobs={"post_fuse": fuse, "post_path": "fragment"}).pixels
        return cache[(name, fuse)]
    return get


def test_every_repository_scene_is_covered():
    """The scenes with neighbourhood effects are among those compared: final (fxaa), brick (fxaa), retro (sharpen)."""
    effects = {name: [s.effect for s in resolve_plan(SCENES / name, None).post_steps]
               for name in ALL_SCENES if not needs_anchors(name)}
    assert "fxaa" in effects["final.toml"] and "fxaa" in effects["brick.toml"] and "sharpen" in effects["retro.toml"]


@pytest.mark.parametrize("name", ALL_SCENES)
def test_scene_exact_with_wgpus_float16_rounding(wgpu_images, name):
    """Raw (rounding toward zero to float16 between per-pixel effects, as lavapipe stores the wgpu path's
    intermediates) == wgpu unfused, bit for bit (threshold 0). Validation with sync validation is on: any message
    raises."""
    raw = render_scene_reference(scene_path(name), size=SIZE, wgpu_intermediates=True)
    assert raw.shape == (SIZE[1], SIZE[0], 4)
    assert len(np.unique(raw[..., :3].reshape(-1, 3), axis=0)) > 1  # an image, not a flat fill
    assert differing(wgpu_images(name, fuse=False), raw) == 0


@pytest.mark.parametrize("name", ALL_SCENES)
def test_scene_matches_wgpu(wgpu_images, name):
    """Raw as it renders by default vs wgpu fused (its default): exact unless a neighbourhood effect is followed
    by a per-pixel one (wgpu keeps float32 there, raw stores the neighbourhood result in an image); then max 1/255
    and FLIP <= 0.005."""
    path = scene_path(name)
    raw, wgpu_pixels = render_scene_reference(path, size=SIZE), wgpu_images(name)
    effects = [s.effect for s in resolve_plan(path, None).post_steps]
    if neighbourhood_then_pixel(effects):
        result = compare_images(wgpu_pixels, raw)
        assert result.max_abs <= 1 and result.flip_mean <= FLIP_THRESHOLD, result.summary()
    else:
        assert differing(wgpu_pixels, raw) == 0


def test_fxaa_pass_changes_edges_only(wgpu_images, tmp_path):
    """The raw FXAA pass does work: final.toml with and without its fxaa entry differ, and only at edges
    (pixels whose 4-neighbourhood range of mean 8-bit value exceeds 2), never in flat regions."""
    text = (SCENES / "final.toml").read_text().replace('"../', f'"{REPO / "assets"}/')
    no_fxaa = tmp_path / "no_fxaa.toml"
    no_fxaa.write_text(text.replace('[[post]]\neffect = "fxaa"\n', ""))
    # float16 between the effects in both, so that FXAA is the only difference
    with_fxaa = render_scene_reference(SCENES / "final.toml", size=SIZE, wgpu_intermediates=True).astype(int)
    without = render_scene_reference(no_fxaa, size=SIZE, wgpu_intermediates=True).astype(int)
    changed = (with_fxaa != without).any(-1)
    assert changed.sum() > 50
    luma = without[..., :3].mean(-1)
    padded = np.pad(luma, 1, mode="edge")
    neighbours = np.stack([padded[:-2, 1:-1], padded[2:, 1:-1], padded[1:-1, :-2], padded[1:-1, 2:], luma])
    contrast = neighbours.max(0) - neighbours.min(0)
    assert (contrast[changed] > 2).all()  # every changed pixel sits on an edge


def test_sharpen_matches_a_numpy_laplacian(tmp_path):
    """sharpen alone on an unlit, flat-coloured scene into rgba16float: the raw GLSL's 3x3 Laplacian ==
    numpy's on the same input (clamp to edge, clamped at 0), within float16 rounding."""
    text = (SCENES / "unlit.toml").read_text().replace('"../', f'"{REPO / "assets"}/')
    assert "hdr = false" in text
    text = text.replace("hdr = false", 'hdr = true\noutput_format = "rgba16float"')
    plain, sharp = tmp_path / "plain.toml", tmp_path / "sharp.toml"
    plain.write_text(text)
    sharp.write_text(text + '\n[[post]]\neffect = "sharpen"\nstrength = 0.5\n')
    src = render_scene_reference(plain, size=SIZE).astype(np.float32)
    got = render_scene_reference(sharp, size=SIZE).astype(np.float32)
    p = np.pad(src[..., :3], ((1, 1), (1, 1), (0, 0)), mode="edge")
    k = 0.5
    expected = np.maximum(src[..., :3] * (1 + 4 * k) - k * (p[:-2, 1:-1] + p[2:, 1:-1] + p[1:-1, :-2] + p[1:-1, 2:]), 0)
    assert not np.allclose(expected, src[..., :3])  # the scene has edges for sharpen to act on
    np.testing.assert_allclose(got[..., :3], expected, rtol=2e-3, atol=1e-3)


def test_split_chain_cuts_before_each_neighbourhood_effect():
    """retro.toml: tonemap, sepia, vignette | sharpen, srgb; final.toml: tonemap | fxaa, vignette."""
    head, segments = split_chain(resolve_plan(SCENES / "retro.toml", None).post_steps)
    assert [p.effect for p in head] == ["tonemap", "sepia", "vignette"]
    assert [(s.effect.effect, [p.effect for p in s.tail]) for s in segments] == [("sharpen", ["srgb"])]
    head, segments = split_chain(resolve_plan(SCENES / "final.toml", None).post_steps)
    assert [p.effect for p in head] == ["tonemap"]
    assert [(s.effect.effect, [p.effect for p in s.tail]) for s in segments] == [("fxaa", ["vignette"])]


def test_reference_command_renders_final(tmp_path):
    """`wgpurender reference assets/scenes/final.toml -o ref.png` writes the raw render (final: fxaa included)."""
    from wgpurender.cli import main
    from wgpurender.core.files.imageio import load_png, to_uint8
    from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY

    out = tmp_path / "ref.png"
    assert main(["reference", str(SCENES / "final.toml"), "-o", str(out), "--size", "96x72"]) == 0
    raw = render_scene_reference(SCENES / "final.toml", size=(96, 72), anisotropy=DEFAULT_ANISOTROPY)
    assert np.array_equal(load_png(out), to_uint8(raw))
