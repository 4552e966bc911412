"""Images to and from disk: atomic PNG writes, and float pixels to 8 bits."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

from .errors import UserError

__all__ = ["UserError", "save_png", "save_image", "image_format", "load_png", "check_writable", "srgb_encode",
           "srgb_decode", "to_uint8"]


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


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_writable(path: str | os.PathLike) -> Path:
    """Fail early, before any rendering, when an output file cannot be written."""
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise UserError(f"cannot write {path}: directory {parent} does not exist (create it first)")
    if not os.access(parent, os.W_OK):
        raise UserError(f"cannot write {path}: directory {parent} is not writable")
    if path.is_dir():
        raise UserError(f"cannot write {path}: it is a directory, give a file name ending in .png")
    return path


def save_png(path: str | os.PathLike, pixels: np.ndarray) -> Path:
    """Write an (H, W, 3|4) image atomically: to a temporary file, then rename.

    A crash or a full disk leaves either the old file or none, never half a PNG.
    """
    path = check_writable(path)
    image = Image.fromarray(to_uint8(np.ascontiguousarray(pixels)))
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    try:
        with os.fdopen(fd, "wb") as f:
            image.save(f, format="PNG")
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600 files; give the usual permissions
        os.replace(tmp, path)
    except OSError as err:
        Path(tmp).unlink(missing_ok=True)
        raise UserError(f"cannot write {path}: {err.strerror or err}") from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def load_png(path: str | os.PathLike) -> np.ndarray:
    """Read an image as (H, W, 4) uint8; a clear error when it is missing or unreadable."""
    path = Path(path)
    if not path.is_file():
        raise UserError(f"image not found: {path}")
    try:
        with Image.open(path) as im:
            return np.asarray(im.convert("RGBA"))
    except (OSError, ValueError) as err:
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


def save_image(path: str | os.PathLike, pixels: np.ndarray) -> Path:
    """Write an (H, W, 3|4) image atomically in the format its suffix names (see :data:`IMAGE_FORMATS`).

    JPEG and BMP have no alpha channel: the alpha is dropped (renders are opaque). JPEG is lossy
    (quality 95): compare images as PNGs.
    """
    fmt = image_format(path)
    if fmt == "PNG":
        return save_png(path, pixels)
    path = check_writable(path)
    image = Image.fromarray(to_uint8(np.ascontiguousarray(pixels)))
    if fmt in _NO_ALPHA:
        image = image.convert("RGB")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    try:
        with os.fdopen(fd, "wb") as f:
            image.save(f, format=fmt, **({"quality": 95} if fmt == "JPEG" else {}))
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except OSError as err:
        Path(tmp).unlink(missing_ok=True)
        raise UserError(f"cannot write {path}: {err.strerror or err}") from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
