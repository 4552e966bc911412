"""Supersampling's resolve: a k-times larger render averaged down to the base size, in linear light.

A box filter over each k x k block is the exact area average for an integer factor k: every output pixel's
square covers exactly k x k whole render pixels, each of weight 1/k^2, so the result is the integral of the
(piecewise-constant) high-resolution image over the output pixel, the same as an ordered-grid supersampling
pattern of k x k samples at the block's pixel centres. A wider windowed filter (Lanczos, Mitchell) would
sharpen or blur relative to that integral; for a ground truth, the plain area integral is the definition.

Averaging must happen in linear light: an 8-bit sRGB image is decoded first (the sRGB curve, float64),
averaged, then encoded and rounded back to 8 bits. Averaging encoded values instead makes a black/white
edge 128 (linear 0.22) rather than 188 (linear 0.5). Alpha is linear already and is averaged as it is.
"""

from __future__ import annotations

import numpy as np

from wgpurender.core.files.imageio import srgb_decode, srgb_encode

_DECODE = srgb_decode(np.arange(256, dtype=np.float64) / 255.0)  # uint8 sRGB -> linear float64


def linear_from_srgb8(pixels: np.ndarray) -> np.ndarray:
    """(H, W, 3|4) uint8 sRGB -> float64 linear RGB (alpha, when present, scaled to [0, 1] without a curve)."""
    pixels = np.asarray(pixels)
    if pixels.dtype != np.uint8:
        raise ValueError(f"expected uint8 sRGB pixels, got {pixels.dtype}")
    out = _DECODE[pixels].copy()
    if pixels.shape[-1] == 4:
        out[..., 3] = pixels[..., 3] / 255.0
    return out


def srgb8_from_linear(linear: np.ndarray) -> np.ndarray:
    """Inverse of :func:`linear_from_srgb8`: encode RGB, round to nearest 8-bit value."""
    linear = np.asarray(linear, dtype=np.float64)
    out = srgb_encode(linear)
    if linear.shape[-1] == 4:
        out[..., 3] = np.clip(linear[..., 3], 0.0, 1.0)
    return np.round(out * 255.0).astype(np.uint8)


def box_average(image: np.ndarray, k: int) -> np.ndarray:
    """Mean of every k x k block of an (H, W, C) float array; H and W must be multiples of k."""
    image = np.asarray(image, dtype=np.float64)
    h, w, c = image.shape
    if k < 1 or h % k or w % k:
        raise ValueError(f"a {w}x{h} image cannot be split into {k}x{k} blocks")
    return image.reshape(h // k, k, w // k, k, c).mean(axis=(1, 3))


def downsample_srgb8(pixels: np.ndarray, k: int) -> np.ndarray:
    """An 8-bit sRGB render at k times the size -> the base size, area-averaged in linear light."""
    if k == 1:
        return np.array(pixels, copy=True)
    return srgb8_from_linear(box_average(linear_from_srgb8(pixels), k))
