"""The HDR target on a bright light, for ``bench accuracy --truth analytic``: what the float scene image is for.

The lit plane of the shading-precision case (accuracy_fidelity.py) under a light of intensity BRIGHT, so the
hot spot is up to three times brighter than 1, then tone-mapped (post ``tonemap``, Reinhard: c / (1 + c), which
keeps everything below infinity distinguishable). The truth is the same curve applied in float64 to the float64
radiance. An 8-bit scene image (rgba8unorm-srgb) clips the radiance at 1 *before* the curve, so every pixel
brighter than 1 comes out at 0.5 (a flat grey-white disc where the truth has a gradient up to 0.76);
rgba16float keeps the range (half floats reach 65504) and rgba32float too. On a dim scene (the
shading-precision case) the three formats are within a step of each other: the format matters only where the
light is bright.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wgpurender.bench.accuracy_fidelity import SHADING_FORMATS, plane_truth, write_plane_scene
from wgpurender.bench.accuracy_knobs import Settings

BRIGHT = 4.0  # the light's intensity: radiance up to about 3 (1.6 stops above 1) on about half the plane
TONEMAP = 'effect = "tonemap"\noperator = "reinhard"'


def reinhard(radiance: np.ndarray) -> np.ndarray:
    """The tone curve in float64: post_tonemap.wgsl's Reinhard, c / (1 + c) per channel."""
    c = np.maximum(np.asarray(radiance, np.float64), 0.0)
    return c / (1.0 + c)


def bright_truth(size: tuple[int, int]) -> np.ndarray:
    return reinhard(plane_truth(size, BRIGHT))


def clipped_fraction(size: tuple[int, int]) -> float:
    """The share of pixels whose truth radiance exceeds 1 in some channel: what an 8-bit target loses."""
    return float((plane_truth(size, BRIGHT) > 1.0).any(axis=-1).mean())


def run_hdr(ctx, work: Path, size: tuple[int, int], frames: int, warmup: int, timed, score) -> list:
    """One row per scene format; ``timed``/``score`` are accuracy_analytic's (the same renderer and timing)."""
    scene = write_plane_scene(work / "plane", size, BRIGHT, TONEMAP, name="bright")
    truth = bright_truth(size)
    note = f"{100 * clipped_fraction(size):.0f}% of pixels above 1"
    return [score("HDR target", fmt, timed(ctx, scene, Settings(msaa=1, format=fmt), size, ("format",), frames,
                                            warmup), truth, note) for fmt in SHADING_FORMATS]
