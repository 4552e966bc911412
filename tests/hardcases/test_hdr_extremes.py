"""HDR extremes through the tone-mapping post effect: 0, denormals, 1e6, 1e20, 3.4e38 and inf stay finite and monotone.

Input: one row of increasing radiances (grey, alpha 1) in an rgba32float or rgba16float texture (in rgba16float
everything above 65504, 1e6 included, is stored as inf), through the tonemap post effect (ACES fitted and Reinhard,
exposure 0, 1 and 1e4) into rgba32float. Required, tolerance 0: every output finite and in [0, 1]; non-decreasing
along the ramp; radiance >= 100 (and inf) maps to >= 0.99 at exposure 1 (a bright sun is white, not black);
exposure 0 gives 0 everywhere, inf included.

Counter-example (the curve without the input clamp, evaluated in float32 like the shader): ACES's rational curve
computes a * a, which overflows at a ~ 1.8e19 and gives inf / inf = NaN; Reinhard gives inf / inf = NaN at inf.
Before shaders_wgsl/post_tonemap.wgsl clamped its input, the GPU showed exactly that on lavapipe: ACES output 0 (NaN
clamped) for radiance >= 1e20 in rgba32float and for 1e6 in rgba16float (stored as inf), Reinhard NaN for inf.
"""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.wgpu_path.device.targets import create_target, read_texture
from wgpurender.wgpu_path.post import PostChain, create_effect

RAMP = np.array(
    [0.0, 1e-45, 1e-40, 1e-38, 1e-6, 0.01, 0.18, 1.0, 4.0, 100.0, 6e4, 1e6, 1e12, 1e19, 1e20, 1e30, 3.4e38, np.inf],
    dtype=np.float32,
)
BRIGHT = RAMP >= 100


def naive_aces(c: np.ndarray) -> np.ndarray:
    """Hill's ACES fit in float32 without an input clamp (the counter-example); grey input, so one channel."""
    c = np.asarray(c, np.float32)
    f = np.float32
    with np.errstate(over="ignore", invalid="ignore"):
        a = c * f(0.59719 + 0.35458 + 0.04823)
        b = (a * (a + f(0.0245786)) - f(0.000090537)) / (a * (f(0.983729) * a + f(0.4329510)) + f(0.238081))
        return b * f(1.60475 - 0.53108 - 0.07367)


def naive_reinhard(c: np.ndarray) -> np.ndarray:
    c = np.asarray(c, np.float32)
    with np.errstate(invalid="ignore"):
        return c / (np.float32(1) + c)


def test_naive_curves_produce_nan():
    assert np.isnan(naive_aces(RAMP[RAMP >= 1e20])).all()
    assert np.isnan(naive_reinhard(RAMP[-1:])).all()


def _tonemap(ctx, source_format: str, **params) -> np.ndarray:
    width = len(RAMP)
    pixels = np.zeros((1, width, 4), np.float32)
    pixels[0, :, :3] = RAMP[:, None]
    pixels[0, :, 3] = 1
    dtype = np.float32 if source_format == "rgba32float" else np.float16
    with np.errstate(over="ignore"):
        data = np.ascontiguousarray(pixels.astype(dtype))  # float16 stores > 65504 as inf, as the GPU would
    source = create_target(ctx, (width, 1), source_format)
    ctx.queue.write_texture(
        {"texture": source, "mip_level": 0, "origin": (0, 0, 0)},
        data,
        {"offset": 0, "bytes_per_row": data.strides[0], "rows_per_image": 1},
        (width, 1, 1),
    )
    target = create_target(ctx, (width, 1), "rgba32float")
    encoder = ctx.device.create_command_encoder()
    PostChain([create_effect("tonemap", **params)]).run(ctx, encoder, source, target)
    ctx.queue.submit([encoder.finish()])
    return read_texture(ctx, target)[0, :, :3].astype(np.float64)


@pytest.mark.parametrize("source_format", ["rgba32float", "rgba16float"])
@pytest.mark.parametrize("operator", ["aces", "reinhard"])
@pytest.mark.parametrize("exposure", [1.0, 1e4])
def test_tonemap_finite_bounded_monotone(ctx, source_format, operator, exposure):
    out = _tonemap(ctx, source_format, operator=operator, exposure=exposure)
    assert np.isfinite(out).all()
    assert out.min() >= 0 and out.max() <= 1
    assert (np.diff(out, axis=0) >= 0).all()
    if exposure == 1.0:
        assert out[BRIGHT].min() >= 0.99
        assert out[0].max() == 0 and out[RAMP <= 1e-38].max() < 1e-6  # zero and denormals stay black


@pytest.mark.parametrize("source_format", ["rgba32float", "rgba16float"])
def test_exposure_zero_is_black_even_for_inf(ctx, source_format):
    out = _tonemap(ctx, source_format, exposure=0.0)
    assert np.isfinite(out).all() and out.max() == 0


# Stephen Hill's ACES fit, as published (ACESInputMat, RRTAndODTFit, ACESOutputMat), rows applied to RGB; float64.
ACES_IN = np.array([[0.59719, 0.35458, 0.04823], [0.07600, 0.90834, 0.01566], [0.02840, 0.13383, 0.83777]])
ACES_OUT = np.array([[1.60475, -0.53108, -0.07367], [-0.10208, 1.10813, -0.00605], [-0.00327, -0.07276, 1.07602]])
F16_MAX = 65504.0


def tone_curve64(radiance: np.ndarray, source_format: str, operator: str, exposure: float) -> np.ndarray:
    """The effect's documented curve in float64: the stored input (float16 rounds, > 65504 is inf), clamped to
    [0, 65504] before and after the exposure, then ACES fitted (clamped to [0, 1]) or Reinhard, per channel."""
    with np.errstate(over="ignore"):
        stored = radiance.astype(np.float16 if source_format == "rgba16float" else np.float32).astype(np.float64)
    c = np.minimum(np.clip(stored, 0.0, F16_MAX) * exposure, F16_MAX)
    rgb = np.repeat(c[:, None], 3, axis=1)
    if operator == "reinhard":
        return rgb / (1.0 + rgb)
    a = rgb @ ACES_IN.T
    b = (a * (a + 0.0245786) - 0.000090537) / (a * (0.983729 * a + 0.4329510) + 0.238081)
    return np.clip(b @ ACES_OUT.T, 0.0, 1.0)


@pytest.mark.parametrize("source_format", ["rgba32float", "rgba16float"])
@pytest.mark.parametrize("operator", ["aces", "reinhard"])
@pytest.mark.parametrize("exposure", [1.0, 0.5, 1e4])
def test_tonemap_equals_the_float64_curve(ctx, source_format, operator, exposure):
    """Every ramp value, 0 to inf, against the curve in float64: float32 arithmetic on the GPU stays within
    2e-6 absolute plus 1e-5 relative (measured on lavapipe, 2026-11-24: at most 1.05e-7)."""
    out = _tonemap(ctx, source_format, operator=operator, exposure=exposure)
    want = tone_curve64(RAMP, source_format, operator, exposure)
    assert np.allclose(out, want, rtol=1e-5, atol=2e-6), np.abs(out - want).max()
