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
- ``detail``: log2 of the ratio of the two images' mean luminance gradient (each + 1/255) over the reference's
  edge pixels, those whose 3x3 neighbourhood spans more than EDGE: sharpening raises edge contrast, FXAA lowers
  it, so dropping either moves it. Restricted to strong edges, it leaves out the texture detail in which
  SwiftShader's filtering differs from lavapipe's (up to 0.13 over every pixel, which a dropped FXAA's 0.10 at
  640x480 did not clear; up to 0.10 over edges, against 0.29-0.45 for a dropped FXAA at every size measured:
  docs/runs/2026-11-27-size-free-bounds).

API-free: numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

RINGS = 5
LIT = 2.0  # a reference pixel is lit above this luminance (1/255): vignette and tone effects scale it
MIN_RING = 0.01  # a ring counts when its lit pixels are at least this share of the image
LUMA = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709, on the 8-bit values as stored
EDGE = 128.0  # an edge pixel's 3x3 neighbourhood spans more than half the range (1/255): silhouettes, sharp lines


@dataclass(frozen=True)
class Structure:
    radial: float  # largest median signed difference of a ring's lit pixels, 1/255
    detail: float  # log2 of actual's mean luminance gradient over expected's, on expected's edge pixels

    def summary(self) -> str:
        return f"radial {self.radial:g}/255, detail {self.detail:+.3f}"


def ring_index(height: int, width: int) -> np.ndarray:
    """Each pixel's ring, 0 (centre) .. RINGS - 1 (corners), by distance from the centre (corner = 1; a pixel
    centre is always nearer, so no ring index reaches RINGS)."""
    y, x = np.mgrid[0:height, 0:width]
    r = np.hypot((x + 0.5 - width / 2) / (width / 2), (y + 0.5 - height / 2) / (height / 2)) / np.sqrt(2)
    return (r * RINGS).astype(int)


def radial_shift(expected: np.ndarray, actual: np.ndarray) -> float:
    """The largest magnitude of a ring's per-channel median of ``actual - expected`` over lit pixels (1/255)."""
    a, b = expected[..., :3].astype(np.float64), actual[..., :3].astype(np.float64)
    h, w = a.shape[:2]
    rings, lit = ring_index(h, w), luminance(a) > LIT
    worst = 0.0
    for ring in range(RINGS):
        inside = (rings == ring) & lit
        if np.count_nonzero(inside) >= MIN_RING * h * w:
            worst = max(worst, float(np.abs(np.median(b[inside] - a[inside], axis=0)).max()))
    return worst


def luminance(image: np.ndarray) -> np.ndarray:
    return image[..., :3].astype(np.float64) @ LUMA


def gradient(y: np.ndarray) -> np.ndarray:
    """Length of the luminance gradient (forward differences, 1/255 per pixel), one row and column short."""
    return np.hypot(np.diff(y, axis=1)[:-1], np.diff(y, axis=0)[:, :-1])


def edge_pixels(y: np.ndarray) -> np.ndarray:
    """Where the 3x3 neighbourhood (edges repeated) spans more than EDGE, on the gradient's grid."""
    h, w = y.shape
    p = np.pad(y, 1, mode="edge")
    around = np.stack([p[i : i + h, j : j + w] for i in range(3) for j in range(3)])
    return (around.max(axis=0) - around.min(axis=0) > EDGE)[:-1, :-1]


def detail_change(expected: np.ndarray, actual: np.ndarray) -> float:
    """log2 of ``actual``'s mean luminance gradient over ``expected``'s (+ 1/255 each), on ``expected``'s edge
    pixels (0 where it has none)."""
    ya, yb = luminance(expected), luminance(actual)
    edges = edge_pixels(ya)
    if not edges.any():
        return 0.0
    return float(np.log2((gradient(yb)[edges].mean() + 1.0) / (gradient(ya)[edges].mean() + 1.0)))


def structure(expected: np.ndarray, actual: np.ndarray) -> Structure:
    """Both measures of ``actual`` against ``expected`` (8-bit, same size; shape checked by the caller)."""
    return Structure(radial_shift(expected, actual), detail_change(expected, actual))
