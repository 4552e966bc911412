"""Post-processing effects against numpy float64 implementations of their formulas.

Input: a 32x24 random HDR image uploaded as rgba16float (values 0..4); the
references are computed in float64 from the same float16-rounded values.
Tolerances: float outputs are rgba16float (11-bit mantissa, relative rounding
2^-11 ~ 5e-4) after float32 shader maths, so rtol 2e-3 + atol 1e-3; 8-bit outputs
are compared to round(255 * reference) within 1 LSB. Chains also round each
intermediate to float16, so they get rtol 4e-3.
"""

from __future__ import annotations

import numpy as np
import pytest
import wgpu
from shading_model import srgb_encode  # the test's own sRGB formula, not the package's

from wgpurender.core.errors import UserError
from wgpurender.wgpu_path.device.gpu_cache import cache_stats
from wgpurender.wgpu_path.device.targets import TARGET_USAGE, create_target, read_texture
from wgpurender.wgpu_path.post import EFFECTS, PostChain, create_effect, effect_names, output_usage, steps_for_target

W, H = 32, 24
RTOL, ATOL = 2e-3, 1e-3
LUMA = np.array([0.2126, 0.7152, 0.0722])


# -- numpy references (float64) ------------------------------------------------
def ref_aces(c: np.ndarray, exposure: float) -> np.ndarray:
    m_in = np.array([[0.59719, 0.35458, 0.04823], [0.07600, 0.90834, 0.01566], [0.02840, 0.13383, 0.83777]])
    m_out = np.array([[1.60475, -0.53108, -0.07367], [-0.10208, 1.10813, -0.00605], [-0.00327, -0.07276, 1.07602]])
    a = (np.maximum(c[..., :3], 0) * exposure) @ m_in.T
    b = (a * (a + 0.0245786) - 0.000090537) / (a * (0.983729 * a + 0.4329510) + 0.238081)
    return np.concatenate([np.clip(b @ m_out.T, 0, 1), c[..., 3:]], axis=-1)


def ref_reinhard(c: np.ndarray, exposure: float) -> np.ndarray:
    x = np.maximum(c[..., :3], 0) * exposure
    return np.concatenate([x / (1 + x), c[..., 3:]], axis=-1)


def smoothstep(e0: float, e1: float, x: np.ndarray) -> np.ndarray:
    t = np.clip((x - e0) / (e1 - e0), 0, 1)
    return t * t * (3 - 2 * t)


def ref_vignette(c: np.ndarray, strength: float, radius: float, softness: float) -> np.ndarray:
    h, w = c.shape[:2]
    y, x = np.mgrid[0:h, 0:w]
    u, v = (x + 0.5) / w, (y + 0.5) / h
    d = np.hypot(u - 0.5, v - 0.5) * np.sqrt(2)
    factor = 1 - strength * smoothstep(radius, radius + softness, d)
    out = c.copy()
    out[..., :3] *= factor[..., None]
    return out


def ref_grayscale(c: np.ndarray, amount: float) -> np.ndarray:
    y = c[..., :3] @ LUMA
    out = c.copy()
    out[..., :3] = c[..., :3] * (1 - amount) + y[..., None] * amount
    return out


def ref_sepia(c: np.ndarray, amount: float) -> np.ndarray:
    m = np.array([[0.393, 0.769, 0.189], [0.349, 0.686, 0.168], [0.272, 0.534, 0.131]])
    out = c.copy()
    out[..., :3] = c[..., :3] * (1 - amount) + (c[..., :3] @ m.T) * amount
    return out


def ref_sharpen(c: np.ndarray, k: float) -> np.ndarray:
    p = np.pad(c, ((1, 1), (1, 1), (0, 0)), mode="edge")
    n, s, w, e = p[:-2, 1:-1], p[2:, 1:-1], p[1:-1, :-2], p[1:-1, 2:]
    out = c.copy()
    out[..., :3] = np.maximum(c[..., :3] * (1 + 4 * k) - k * (n + s + w + e)[..., :3], 0)
    return out


# -- GPU helpers ---------------------------------------------------------------
@pytest.fixture(scope="module")
def hdr_image() -> np.ndarray:
    rng = np.random.default_rng(7)
    img = rng.uniform(0.0, 4.0, (H, W, 4))
    img[..., 3] = rng.uniform(0, 1, (H, W))
    return img.astype(np.float16)


def upload(ctx, pixels: np.ndarray) -> wgpu.GPUTexture:
    """An rgba16float texture holding ``pixels`` (H, W, 4) float16."""
    h, w = pixels.shape[:2]
    tex = create_target(ctx, (w, h), "rgba16float", label="post-test-input")
    data = np.ascontiguousarray(pixels, dtype=np.float16)
    ctx.queue.write_texture({"texture": tex}, data.tobytes(), {"bytes_per_row": w * 8, "rows_per_image": h}, (w, h, 1))
    return tex


def ToneMap(**params):  # noqa: N802  (reads like the effect's name in the parametrisations below)
    return create_effect("tonemap", **params)


def Vignette(**params):  # noqa: N802
    return create_effect("vignette", **params)


def SrgbEncode():  # noqa: N802
    return create_effect("srgb")


def run_chain(ctx, effects, pixels: np.ndarray, fmt: str = "rgba16float", *, fuse: bool = True,
              path: str = "fragment") -> np.ndarray:
    """The chain run on ``pixels``; on the compute path the target gets the storage usage the plan asks for."""
    src = upload(ctx, pixels)
    chain = PostChain(effects, fuse=fuse, path=path)
    size = (pixels.shape[1], pixels.shape[0])
    passes, _ = chain.plan("rgba16float", fmt, size)
    dst = create_target(ctx, size, fmt, usage=TARGET_USAGE | output_usage(passes))
    encoder = ctx.device.create_command_encoder()
    chain.run(ctx, encoder, src, dst)
    ctx.queue.submit([encoder.finish()])
    out = read_texture(ctx, dst)
    return out.astype(np.float64) if out.dtype != np.uint8 else out


def as64(img: np.ndarray) -> np.ndarray:
    return img.astype(np.float64)


# -- each effect against its formula --------------------------------------------
@pytest.mark.parametrize(
    ("effect", "reference"),
    [
        (ToneMap(exposure=1.5), lambda c: ref_aces(c, 1.5)),
        (ToneMap(exposure=0.7, operator="reinhard"), lambda c: ref_reinhard(c, 0.7)),
        (Vignette(strength=0.8, radius=0.3, softness=0.6), lambda c: ref_vignette(c, 0.8, 0.3, 0.6)),
        (create_effect("grayscale", amount=0.7), lambda c: ref_grayscale(c, 0.7)),
        (create_effect("sepia"), lambda c: ref_sepia(c, 1.0)),
        (create_effect("sharpen", strength=0.6), lambda c: ref_sharpen(c, 0.6)),
    ],
    ids=["aces", "reinhard", "vignette", "grayscale", "sepia", "sharpen"],
)
@pytest.mark.parametrize("path", ["fragment", "compute"])
def test_effect_matches_numpy(ctx, hdr_image, effect, reference, path):
    """Each effect on both post paths (a full-screen triangle, and a dispatch writing a storage texture)."""
    got = run_chain(ctx, [effect], hdr_image, path=path)
    want = reference(as64(hdr_image))
    np.testing.assert_allclose(got, want, rtol=RTOL, atol=ATOL)


def test_tonemap_output_is_in_unit_range_and_monotonic(ctx):
    """ACES maps 0 -> ~0 and large values to <= 1, increasing along a ramp."""
    ramp = np.zeros((1, 64, 4), dtype=np.float16)
    ramp[0, :, :3] = np.geomspace(1e-3, 60.0, 64)[:, None]
    ramp[0, :, 3] = 1
    got = run_chain(ctx, [ToneMap()], ramp)[0, :, 0]
    assert got.min() >= 0 and got.max() <= 1.0
    assert np.all(np.diff(got) >= -1e-3)
    assert got[-1] > 0.99


@pytest.mark.parametrize("path", ["fragment", "compute"])
@pytest.mark.parametrize("fmt", ["rgba8unorm", "rgba8unorm-srgb", "bgra8unorm", "bgra8unorm-srgb"])
def test_srgb_effect_encodes_exactly_once(ctx, fmt, path):
    """Both 8-bit targets store round(255 * srgb_encode(x)) within 1 LSB: the shader encodes
    for rgba8unorm, the hardware for rgba8unorm-srgb, never both. On the compute path an -srgb target
    is written through an rgba8unorm scratch that the shader encodes (then copied), a bgra target by a
    fragment pass (it cannot be a storage texture): still exactly once."""
    ramp = np.zeros((4, 64, 4), dtype=np.float16)
    ramp[..., :3] = np.linspace(0, 1, 64)[None, :, None]
    ramp[..., 3] = 1
    got = run_chain(ctx, [SrgbEncode()], ramp, fmt, path=path).astype(int)
    want = np.round(srgb_encode(as64(ramp)[..., :3]) * 255).astype(int)
    assert np.abs(got[..., :3] - want).max() <= 1


def test_srgb_effect_keeps_float_targets_linear(ctx, hdr_image):
    got = run_chain(ctx, [SrgbEncode()], hdr_image, "rgba16float")
    np.testing.assert_array_equal(got, as64(hdr_image))


def test_chain_appends_srgb_for_plain_unorm_target(ctx):
    """tonemap alone into rgba8unorm gets an implicit srgb pass: bytes = encode(tonemap(x))."""
    img = np.full((8, 8, 4), 0.5, dtype=np.float16)
    assert [s.effect for s in steps_for_target([ToneMap()], "rgba8unorm")] == ["tonemap", "srgb"]
    assert [s.effect for s in steps_for_target([ToneMap()], "rgba8unorm-srgb")] == ["tonemap"]
    got = run_chain(ctx, [ToneMap()], img, "rgba8unorm").astype(int)
    want = np.round(srgb_encode(ref_aces(as64(img), 1.0)[..., :3]) * 255).astype(int)
    assert np.abs(got[..., :3] - want).max() <= 1


# -- FXAA -----------------------------------------------------------------------
EDGE_SLOPE, EDGE_OFFSET = 0.35, 6.0


def aliased_edge(w: int = 48, h: int = 32) -> np.ndarray:
    """White above the line y = 0.35 x + 6, black below, sampled at pixel centres: a hard staircase."""
    y, x = np.mgrid[0:h, 0:w]
    inside = (y + 0.5) < EDGE_SLOPE * (x + 0.5) + EDGE_OFFSET
    img = np.zeros((h, w, 4), dtype=np.float16)
    img[..., :3] = inside[..., None]
    img[..., 3] = 1
    return img


def edge_coverage(w: int = 48, h: int = 32, n: int = 16) -> np.ndarray:
    """The ideal anti-aliased image: the fraction of each pixel above the line (n x n supersamples)."""
    y, x = np.mgrid[0 : h * n, 0 : w * n]
    inside = (y + 0.5) / n < EDGE_SLOPE * (x + 0.5) / n + EDGE_OFFSET
    return inside.reshape(h, n, w, n).mean(axis=(1, 3))


@pytest.mark.parametrize("path", ["fragment", "compute"])
def test_fxaa_smooths_aliased_edge_and_keeps_flat_regions(ctx, path):
    """Flat 3x3 neighbourhoods come back bit-exact (FXAA's early exit); staircase pixels (a 4-neighbour
    differs) move to intermediate values, towards the other side, and the mean absolute error against
    the true pixel coverage drops to under half of the aliased image's."""
    img = aliased_edge()
    got = run_chain(ctx, [create_effect("fxaa")], img, path=path)
    lum = as64(img)[..., 0]
    p = np.pad(lum, 1, mode="edge")
    window = np.stack([p[dy : dy + lum.shape[0], dx : dx + lum.shape[1]] for dy in range(3) for dx in range(3)])
    flat = window.min(axis=0) == window.max(axis=0)
    np.testing.assert_array_equal(got[flat], as64(img)[flat])

    cross = np.stack([p[:-2, 1:-1], p[2:, 1:-1], p[1:-1, :-2], p[1:-1, 2:]])
    edge = np.any(cross != lum, axis=0)
    g = got[..., 0][edge]
    blended = (g > 0.02) & (g < 0.98)
    assert blended.mean() > 0.6, f"only {blended.mean():.0%} of staircase pixels blended"
    assert got.min() >= 0 and got.max() <= 1 + 1e-3
    moved = got[..., 0] - lum
    assert np.all(moved[lum == 1] <= 1e-3) and np.all(moved[lum == 0] >= -1e-3)

    truth = edge_coverage()
    aliased_err = np.abs(lum - truth)[edge].mean()
    fxaa_err = np.abs(got[..., 0] - truth)[edge].mean()
    assert fxaa_err < 0.5 * aliased_err, f"FXAA error {fxaa_err:.3f} vs aliased {aliased_err:.3f}"


# -- chains -------------------------------------------------------------------
@pytest.mark.parametrize(("fuse", "path"), [(True, "fragment"), (False, "fragment"), (True, "compute")])
def test_two_effects_equal_composition(ctx, hdr_image, fuse, path):
    got = run_chain(ctx, [ToneMap(exposure=1.2), Vignette(strength=0.6)], hdr_image, fuse=fuse, path=path)
    want = ref_vignette(ref_aces(as64(hdr_image), 1.2), 0.6, 0.5, 0.5)
    np.testing.assert_allclose(got, want, rtol=2 * RTOL, atol=ATOL)


def test_three_effects_use_both_intermediates(ctx, hdr_image):
    """sharpen -> grayscale -> tonemap: A then B then the output; each intermediate rounded to float16."""
    effects = [create_effect("sharpen", strength=0.3), create_effect("grayscale"), ToneMap(operator="reinhard")]
    got = run_chain(ctx, effects, hdr_image, fuse=False)
    f16 = lambda a: a.astype(np.float16).astype(np.float64)  # noqa: E731
    want = ref_reinhard(f16(ref_grayscale(f16(ref_sharpen(as64(hdr_image), 0.3)), 1.0)), 1.0)
    np.testing.assert_allclose(got, want, rtol=2 * RTOL, atol=ATOL)
    passes, attachments = PostChain(effects, fuse=False).plan("rgba16float", "rgba16float", (W, H))
    assert [p.output for p in passes] == ["post_a", "post_b", "output"]
    # fused, the three are one pass (grayscale and tonemap need only the pixel sharpen computed): no float16
    # rounding between them
    got = run_chain(ctx, effects, hdr_image, fuse=True)
    want = ref_reinhard(ref_grayscale(f16(ref_sharpen(as64(hdr_image), 0.3)), 1.0), 1.0)
    np.testing.assert_allclose(got, want, rtol=2 * RTOL, atol=ATOL)
    passes, attachments = PostChain(effects, fuse=True).plan("rgba16float", "rgba16float", (W, H))
    assert [p.effect for p in passes] == ["sharpen+grayscale+tonemap"] and attachments == []


def test_empty_chain_records_nothing(ctx, hdr_image):
    """An empty chain does not touch the target (the plan draws the scene straight into it instead)."""
    chain = PostChain([])
    assert not chain and chain.plan("rgba16float", "rgba8unorm", (W, H)) == ([], [])
    src = upload(ctx, hdr_image)
    dst = upload(ctx, np.full_like(hdr_image, 0.25))
    encoder = ctx.device.create_command_encoder()
    chain.run(ctx, encoder, src, dst)
    ctx.queue.submit([encoder.finish()])
    np.testing.assert_array_equal(read_texture(ctx, dst), np.full_like(hdr_image, 0.25))


# -- API: errors, caching, descriptions ------------------------------------------
def test_srgb_must_be_last():
    with pytest.raises(UserError, match="'srgb' must be the last"):
        PostChain([SrgbEncode(), ToneMap()])


def test_unknown_effect_and_parameter():
    with pytest.raises(UserError, match="unknown post effect 'bloom'.*fxaa, grayscale, sepia, sharpen, srgb"):
        create_effect("bloom")
    with pytest.raises(UserError, match="no parameter 'gamma'.*exposure, operator"):
        create_effect("tonemap", gamma=2.2)
    with pytest.raises(UserError, match="operator must be one of aces, reinhard"):
        create_effect("tonemap", operator="filmic")
    with pytest.raises(UserError, match="strength must be in"):
        create_effect("vignette", strength=3)


def test_pipelines_cached_per_shader_and_format(ctx, hdr_image, monkeypatch):
    """Parameters live in a uniform buffer, not in the shader: a second chain of the same effects with other
    values makes no new pipeline (the device's "post-pipelines" cache hits); another target format does."""
    monkeypatch.delattr(ctx.device, "_wgpurender_caches", raising=False)  # start from empty device caches
    run_chain(ctx, [ToneMap(exposure=1.0)], hdr_image)
    before = cache_stats(ctx.device)["post-pipelines"]
    run_chain(ctx, [ToneMap(exposure=3.0)], hdr_image)
    after = cache_stats(ctx.device)["post-pipelines"]
    assert (after["misses"], after["hits"]) == (before["misses"], before["hits"] + 1)
    run_chain(ctx, [ToneMap(exposure=3.0)], hdr_image, "rgba8unorm-srgb")
    assert cache_stats(ctx.device)["post-pipelines"]["misses"] == after["misses"] + 1


def test_chain_plan():
    chain = PostChain([ToneMap(exposure=2), create_effect("fxaa")], fuse=False)
    passes, _ = chain.plan("rgba16float", "rgba8unorm", (W, H))
    assert [p.effect for p in passes] == ["tonemap", "fxaa", "srgb"]
    assert [(p.input_format, p.output_format) for p in passes] == [
        ("rgba16float", "rgba16float"),
        ("rgba16float", "rgba16float"),
        ("rgba16float", "rgba8unorm"),
    ]
    assert passes[0].steps[0].values == {"exposure": 2.0, "operator": "aces"}
    assert "applies the sRGB curve" in passes[2].notes[0]
    fused, _ = PostChain([ToneMap(exposure=2), create_effect("fxaa")]).plan("rgba16float", "rgba8unorm", (W, H))
    assert [p.effect for p in fused] == ["tonemap", "fxaa+srgb"]
    required = {"tonemap", "srgb", "fxaa", "vignette", "grayscale", "sepia", "sharpen"}
    assert set(effect_names()) == set(EFFECTS) >= required
