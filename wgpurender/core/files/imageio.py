"""Images to and from disk: atomic PNG writes, and float pixels to 8 bits."""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np
from PIL import Image

from wgpurender.core.errors import UserError
from wgpurender.core.files.input_files import check_image_pixels, input_file
from wgpurender.core.files.safe_write import atomic_write, output_target

__all__ = ["UserError", "save_png", "save_image", "image_format", "load_png", "check_writable", "decode_image",
           "encode_png", "encode_image", "srgb_encode", "srgb_decode", "to_uint8"]


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1), linear [0, 1] -> encoded [0, 1]."""
    x = np.clip(np.nan_to_num(np.asarray(linear, dtype=np.float64)), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def srgb_decode(encoded: np.ndarray) -> np.ndarray:
    """Inverse of :func:`srgb_encode`."""
    x = np.asarray(encoded, dtype=np.float64)
    return np.where(x <= 0.04045, x / 12.92, np.power((x + 0.055) / 1.055, 2.4))


def to_uint8(pixels: np.ndarray) -> np.ndarray:
    """8-bit pixels for a PNG. uint8 passes through; float pixels are linear and get sRGB-encoded."""
    if pixels.dtype == np.uint8:
        return pixels
    return np.round(srgb_encode(pixels) * 255.0).astype(np.uint8)


def check_writable(path: str | os.PathLike) -> Path:
    """Fail early, before any rendering, when an output file cannot or must not be written (safe_write's rules)."""
    return output_target(path)


def encode_png(pixels: np.ndarray) -> bytes:
    """PNG bytes of an (H, W, 3|4) image (float pixels are linear and get sRGB-encoded)."""
    buffer = io.BytesIO()
    Image.fromarray(to_uint8(np.ascontiguousarray(pixels))).save(buffer, format="PNG")
    return buffer.getvalue()


def save_png(path: str | os.PathLike, pixels: np.ndarray) -> Path:
    """Write an (H, W, 3|4) image atomically: encoded in memory, written to a temporary file, then renamed.

    A crash, a signal or a full disk leaves either the old file or none, never half a PNG; see
    :mod:`wgpurender.core.files.safe_write` for what each exit path leaves and which targets are refused.
    """
    output_target(path)
    return atomic_write(path, lambda: encode_png(pixels))


def decode_image(image: Image.Image, name: str) -> np.ndarray:
    """(H, W, 4) uint8 from any Pillow image: 16-bit and 32-bit integer greyscale are scaled to 8 bits
    (Pillow's own convert("RGBA") would clip them at 255), and every channel layout becomes RGBA.
    The size the header declares is checked first (:func:`check_image_pixels`): nothing is decoded before."""
    check_image_pixels(*image.size, name)
    if image.mode in ("I", "I;16", "I;16B", "I;16L", "I;16N"):
        wide = np.asarray(image).astype(np.float64)
        if wide.size and (wide.min() < 0 or wide.max() > 65535):
            raise UserError(f"cannot read image {name}: {image.mode} pixels outside 0..65535")
        gray = np.round(wide / 257.0).astype(np.uint8)
        image = Image.fromarray(gray, "L")
    elif image.mode == "F":
        raise UserError(f"cannot read image {name}: floating-point images are not supported; save it as 8- or 16-bit")
    return np.asarray(image.convert("RGBA"))


PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
PNG_CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}  # IHDR colour type -> samples per pixel


def check_png_complete(source, name: str) -> None:
    """UserError when a PNG's image data ends before the rows its header declares (a complete zlib stream of
    fewer rows): Pillow decodes such a file at the declared size, the missing rows zero-filled, without an error.
    Other formats, interlaced PNGs and unreadable headers are left to Pillow. ``source``: a path or a binary file
    object (read from its start, then rewound)."""
    import struct
    import zlib

    f = open(source, "rb") if isinstance(source, (str, os.PathLike)) else source
    start = f.tell()
    f.seek(0)
    try:
        if f.read(8) != PNG_SIGNATURE:
            return
        expected = produced = 0
        inflate = zlib.decompressobj()
        while True:
            head = f.read(8)
            if len(head) < 8:
                break
            length, kind = struct.unpack(">I4s", head)
            data = f.read(length)
            f.read(4)  # CRC (Pillow checks it)
            if kind == b"IHDR" and len(data) >= 13:
                width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", data[:13])
                if interlace or colour not in PNG_CHANNELS:
                    return
                expected = height * (1 + (width * depth * PNG_CHANNELS[colour] + 7) // 8)
            elif kind == b"IDAT" and expected:
                chunk = data
                while chunk and produced < expected:
                    produced += len(inflate.decompress(chunk, 1 << 20))
                    chunk = inflate.unconsumed_tail
            elif kind == b"IEND" or produced >= expected > 0:
                break
    except (OSError, zlib.error, struct.error):
        return  # Pillow reports a broken file in its own words
    finally:
        if f is not source:
            f.close()
        else:
            f.seek(start)
    if expected and produced < expected:
        raise UserError(f"cannot read image {name}: its data ends early ({100 * produced / expected:.0f}% of the "
                        "rows its header declares); the file is truncated: save it again")


def load_png(path: str | os.PathLike) -> np.ndarray:
    """Read an image as (H, W, 4) uint8; a clear error when it is missing or unreadable."""
    path = input_file(path, "image")
    check_png_complete(path, str(path))
    try:
        with Image.open(path) as im:
            return decode_image(im, str(path))
    except (OSError, ValueError, Image.DecompressionBombError) as err:
        raise UserError(f"cannot read image {path}: {err}") from None


# The output format follows the file's suffix: PNG (lossless, what every comparison here reads),
# or another format Pillow writes when the user asks for it by name. An unknown or missing
# suffix is refused rather than written as a PNG under a misleading name.
IMAGE_FORMATS = {".png": "PNG", ".jpg": "JPEG", ".jpeg": "JPEG", ".bmp": "BMP", ".tif": "TIFF", ".tiff": "TIFF",
                 ".webp": "WEBP"}
_NO_ALPHA = ("JPEG", "BMP")


def image_format(path: str | os.PathLike) -> str:
    """Pillow's format name for an output path's suffix; a UserError for a suffix we do not write."""
    suffix = Path(path).suffix.lower()
    if suffix not in IMAGE_FORMATS:
        shown = f"suffix {suffix!r}" if suffix else "no suffix"
        raise UserError(f"cannot write {path}: {shown}; name the file .png (lossless), or "
                        f"{', '.join(s for s in IMAGE_FORMATS if s != '.png')}")
    return IMAGE_FORMATS[suffix]


def encode_image(pixels: np.ndarray, fmt: str) -> bytes:
    """The image's bytes in a Pillow format (JPEG/BMP without alpha, JPEG at quality 95)."""
    if fmt == "PNG":
        return encode_png(pixels)
    image = Image.fromarray(to_uint8(np.ascontiguousarray(pixels)))
    if fmt in _NO_ALPHA:
        image = image.convert("RGB")
    buffer = io.BytesIO()
    image.save(buffer, format=fmt, **({"quality": 95} if fmt == "JPEG" else {}))
    return buffer.getvalue()


def save_image(path: str | os.PathLike, pixels: np.ndarray) -> Path:
    """Write an (H, W, 3|4) image atomically in the format its suffix names (see :data:`IMAGE_FORMATS`),
    with :func:`save_png`'s guarantees (:mod:`wgpurender.core.files.safe_write`).

    JPEG and BMP have no alpha channel: the alpha is dropped (renders are opaque). JPEG is lossy
    (quality 95): compare images as PNGs.
    """
    fmt = image_format(path)
    output_target(path)
    return atomic_write(path, lambda: encode_image(pixels, fmt))
