"""Image comparison: the numbers that say how far two renders are apart, and a heatmap that shows where.

FLIP (NVIDIA's perceptual difference, through the flip-evaluator package) is the
headline metric for lit scenes, where a 1/255 rule is too strict for honest
differences in filtering and rasterisation; PSNR and the share of pixels off by
more than 1/255 or 2/255 are the plain ones.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from wgpurender.core.errors import UserError

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


def _same_size(reference: np.ndarray, test: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    a, b = _rgb8(reference, "reference"), _rgb8(test, "test")
    if a.shape != b.shape:
        raise UserError(f"images differ in size: {a.shape[1]}x{a.shape[0]} vs {b.shape[1]}x{b.shape[0]}")
    return a, b


def flip_mean(a: np.ndarray, b: np.ndarray) -> tuple[float, np.ndarray]:
    """Mean LDR FLIP error of b against reference a (both sRGB uint8), and the error map."""
    import flip_evaluator

    ref = np.ascontiguousarray(a, dtype=np.float32) / 255.0
    test = np.ascontiguousarray(b, dtype=np.float32) / 255.0
    error_map, mean, _ = flip_evaluator.evaluate(ref, test, "LDR", applyMagma=False)
    return float(mean), np.asarray(error_map).reshape(a.shape[:2])


def compare_images(reference: np.ndarray, test: np.ndarray, *, with_flip: bool = True) -> Comparison:
    """Compare two 8-bit images of the same size."""
    a, b = _same_size(reference, test)
    diff = np.abs(a.astype(np.int16) - b.astype(np.int16))
    mse = float(np.mean((diff.astype(np.float64) / 255.0) ** 2))
    per_pixel = diff.max(axis=-1)
    return Comparison(
        psnr=float("inf") if mse == 0 else 10 * np.log10(1.0 / mse),
        max_abs=int(diff.max()),
        over_1=float(np.mean(per_pixel > 1)),
        over_2=float(np.mean(per_pixel > 2)),
        # FLIP of two equal images is 0 by its definition (no colour or feature difference): skip the filters
        flip_mean=(flip_mean(a, b)[0] if mse > 0 else 0.0) if with_flip else float("nan"),
    )


def heatmap(reference: np.ndarray, test: np.ndarray, gain: float = 32.0) -> np.ndarray:
    """An RGB image of where the two differ: black = equal, bright = different.

    The largest channel difference is multiplied by ``gain`` (32: a 1/255 difference
    becomes 32/255, visible) and mapped through a black-red-yellow-white ramp.
    """
    a, b = _same_size(reference, test)
    d = np.abs(a.astype(np.float64) - b.astype(np.float64)).max(axis=-1) * gain / 255.0
    return _ramp(d)


def _ramp(d: np.ndarray) -> np.ndarray:
    """Black-red-yellow-white for d in [0, 1] (clipped), as 8-bit RGB."""
    d = np.clip(d, 0.0, 1.0)
    ramp = np.stack([np.clip(3 * d, 0, 1), np.clip(3 * d - 1, 0, 1), np.clip(3 * d - 2, 0, 1)], axis=-1)
    return np.round(ramp * 255).astype(np.uint8)


SCALE_BAR = (12, 16, 4)  # bar height, label line height, margin (pixels)


def heatmap_with_scale(reference: np.ndarray, test: np.ndarray, gain: float = 32.0) -> np.ndarray:
    """:func:`heatmap` with its colour scale drawn below it: the ramp from no difference to the difference
    that saturates (255/gain, in 1/255 units), labelled. At least 200 pixels wide, so the labels fit."""
    from PIL import Image, ImageDraw

    image = heatmap(reference, test, gain)
    h, w = image.shape[:2]
    bar_h, line_h, margin = SCALE_BAR
    width = max(w, 200)
    out = np.zeros((h + margin + bar_h + line_h, width, 3), np.uint8)
    out[:h, :w] = image
    bar_w = width - 2 * margin
    out[h + margin : h + margin + bar_h, margin : margin + bar_w] = _ramp(np.linspace(0.0, 1.0, bar_w))[None]
    canvas = Image.fromarray(out)
    draw = ImageDraw.Draw(canvas)
    saturation = 255.0 / gain
    y = h + margin + bar_h + 2
    draw.text((margin, y), "0", fill=(255, 255, 255))
    right = f">= {saturation:.3g}/255"
    draw.text((margin + bar_w - draw.textlength(right), y), right, fill=(255, 255, 255))
    middle = f"{saturation / 2:.3g}"
    draw.text((margin + bar_w // 2 - draw.textlength(middle) / 2, y), middle, fill=(255, 255, 255))
    return np.asarray(canvas)
