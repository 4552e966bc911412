"""Size-free measures of what a post effect does to a whole image (issue 32, item 6).

Two implementations of the course differ by rasterisation, filtering and rounding: local differences of both
signs, where most pixels of any large region stay equal. A dropped post effect is a systematic change instead.
max, the changed share and FLIP cannot tell the two apart (a removed vignette moves pixels by at most 5/255,
less than the browser's own differences), so the matrix bounds two more measures, neither of which grows with
the image size:

- ``radial``: the image cut into RINGS rings around its centre (distance normalised so the corner is 1); in
  each ring the median of the signed difference over the reference's lit pixels, per channel; the largest
  magnitude (1/255). A median is 0 unless most of a ring moved one way: tone mapping, sepia and a vignette
  (darker towards the corners) do, sign-balanced implementation differences do not. Black pixels are left out
  because a multiplicative effect cannot change them (a scene on black would hide its vignette).
- ``detail``: log2 of the ratio of the mean luminance gradient of the two images (each + 1/255, so a flat
  image reads 0): sharpening raises it, FXAA lowers it, so dropping either moves it.

API-free: numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

RINGS = 5
LIT = 2.0  # a reference pixel is lit above this luminance (1/255): vignette and tone effects scale it
MIN_RING = 0.01  # a ring counts when its lit pixels are at least this share of the image
LUMA = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709, on the 8-bit values as stored


@dataclass(frozen=True)
class Structure:
    radial: float  # largest median signed difference of a ring's lit pixels, 1/255
    detail: float  # log2 of actual's mean luminance gradient over expected's

    def summary(self) -> str:
        return f"radial {self.radial:g}/255, detail {self.detail:+.3f}"


def ring_index(height: int, width: int) -> np.ndarray:
    """Each pixel's ring, 0 (centre) .. RINGS - 1 (corners), by distance from the centre (corner = 1)."""
    y, x = np.mgrid[0:height, 0:width]
    r = np.hypot((x + 0.5 - width / 2) / (width / 2), (y + 0.5 - height / 2) / (height / 2)) / np.sqrt(2)
    return np.minimum((r * RINGS).astype(int), RINGS - 1)


def radial_shift(expected: np.ndarray, actual: np.ndarray) -> float:
    """The largest magnitude of a ring's per-channel median of ``actual - expected`` over lit pixels (1/255)."""
    a, b = expected[..., :3].astype(np.float64), actual[..., :3].astype(np.float64)
    h, w = a.shape[:2]
    rings, lit = ring_index(h, w), a @ LUMA > LIT
    worst = 0.0
    for ring in range(RINGS):
        inside = (rings == ring) & lit
        if np.count_nonzero(inside) >= MIN_RING * h * w:
            worst = max(worst, float(np.abs(np.median(b[inside] - a[inside], axis=0)).max()))
    return worst


def mean_gradient(image: np.ndarray) -> float:
    """Mean length of the luminance gradient (forward differences, 1/255 per pixel)."""
    y = image[..., :3].astype(np.float64) @ LUMA
    return float(np.hypot(np.diff(y, axis=1)[:-1], np.diff(y, axis=0)[:, :-1]).mean())


def detail_change(expected: np.ndarray, actual: np.ndarray) -> float:
    """log2 of ``actual``'s mean luminance gradient over ``expected``'s (+ 1/255 each)."""
    return float(np.log2((mean_gradient(actual) + 1.0) / (mean_gradient(expected) + 1.0)))


def structure(expected: np.ndarray, actual: np.ndarray) -> Structure:
    """Both measures of ``actual`` against ``expected`` (8-bit, same size; shape checked by the caller)."""
    return Structure(radial_shift(expected, actual), detail_change(expected, actual))
