"""Image comparison: the numbers that say how far two renders are apart, and a heatmap that shows where.

FLIP (NVIDIA's perceptual difference, through the flip-evaluator package) is the
headline metric for lit scenes, where a 1/255 rule is too strict for honest
differences in filtering and rasterisation; PSNR and the share of pixels off by
more than 1/255 or 2/255 are the plain ones.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from .errors import UserError

METRICS = ("psnr", "max_abs", "over_1", "over_2", "flip_mean")


@dataclass(frozen=True)
class Comparison:
    psnr: float  # dB over RGB, inf for identical images
    max_abs: int  # largest difference of any RGB channel, in 1/255 units
    over_1: float  # share of pixels with any channel off by more than 1/255
    over_2: float  # ... by more than 2/255
    flip_mean: float  # mean LDR FLIP error, 0 (identical) .. 1

    def as_dict(self) -> dict:
        return asdict(self)

    def summary(self) -> str:
        return (
            f"PSNR {self.psnr:.2f} dB, max abs diff {self.max_abs}/255, "
            f"pixels over 1/255: {100 * self.over_1:.3f}%, over 2/255: {100 * self.over_2:.3f}%, "
            f"FLIP mean {self.flip_mean:.5f}"
        )


def _rgb8(image: np.ndarray, name: str) -> np.ndarray:
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] not in (3, 4):
        raise UserError(f"{name}: expected an RGB or RGBA image, got an array of shape {image.shape}")
    if image.dtype != np.uint8:
        raise UserError(f"{name}: expected 8-bit pixels, got {image.dtype}")
    return image[..., :3]


def flip_mean(a: np.ndarray, b: np.ndarray) -> tuple[float, np.ndarray]:
    """Mean LDR FLIP error of b against reference a (both sRGB uint8), and the error map."""
    import flip_evaluator

    ref = np.ascontiguousarray(a, dtype=np.float32) / 255.0
    test = np.ascontiguousarray(b, dtype=np.float32) / 255.0
    error_map, mean, _ = flip_evaluator.evaluate(ref, test, "LDR", applyMagma=False)
    return float(mean), np.asarray(error_map).reshape(a.shape[:2])


def compare_images(reference: np.ndarray, test: np.ndarray, *, with_flip: bool = True) -> Comparison:
    """Compare two 8-bit images of the same size."""
    a, b = _rgb8(reference, "reference"), _rgb8(test, "test")
    if a.shape != b.shape:
        raise UserError(f"images differ in size: {a.shape[1]}x{a.shape[0]} vs {b.shape[1]}x{b.shape[0]}")
    diff = np.abs(a.astype(np.int16) - b.astype(np.int16))
    mse = float(np.mean((diff.astype(np.float64) / 255.0) ** 2))
    per_pixel = diff.max(axis=-1)
    return Comparison(
        psnr=float("inf") if mse == 0 else 10 * np.log10(1.0 / mse),
        max_abs=int(diff.max()),
        over_1=float(np.mean(per_pixel > 1)),
        over_2=float(np.mean(per_pixel > 2)),
        flip_mean=flip_mean(a, b)[0] if with_flip else float("nan"),
    )


def heatmap(reference: np.ndarray, test: np.ndarray, gain: float = 32.0) -> np.ndarray:
    """An RGB image of where the two differ: black = equal, bright = different.

    The largest channel difference is multiplied by ``gain`` (32: a 1/255 difference
    becomes 32/255, visible) and mapped through a black-red-yellow-white ramp.
    """
    a, b = _rgb8(reference, "reference"), _rgb8(test, "test")
    d = np.abs(a.astype(np.float64) - b.astype(np.float64)).max(axis=-1) * gain / 255.0
    d = np.clip(d, 0.0, 1.0)
    ramp = np.stack([np.clip(3 * d, 0, 1), np.clip(3 * d - 1, 0, 1), np.clip(3 * d - 2, 0, 1)], axis=-1)
    return np.round(ramp * 255).astype(np.uint8)
