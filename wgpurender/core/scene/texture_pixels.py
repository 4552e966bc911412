"""Images and arrays to RGBA8 pixels, and mip-chain sizes: the API-free half of texture loading.

Both paths upload what these functions return (wgpurender/wgpu_path/device/textures.py on wgpu,
wgpurender/raw_path/device/textures.py on raw Vulkan), so a file becomes the same bytes on both.

Pixel rules (also in the error messages):
- RGB, RGBA, L, LA, 1-bit, CMYK, YCbCr and palette (P, PA) images become RGBA8 through
  Pillow's ``convert("RGBA")`` (palette transparency becomes alpha).
- 16-bit images (Pillow modes I;16*, and I when every value is within 0..65535) keep
  their high byte: ``v8 = v16 >> 8``. That is the rule Pillow itself applies when it
  decodes a 16-bit RGB(A) PNG into RGB(A), so a 16-bit grey and a 16-bit colour file
  holding the same values end up with the same bytes. Float images (mode F) are refused.
- numpy arrays: (H, W) or (H, W, 1..4); uint8 as is, uint16 by the same >> 8 rule,
  float arrays in [0, 1] quantised as round(v * 255) with no transfer function applied
  (the values are stored as they are: give sRGB-encoded floats for an sRGB texture).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from PIL import Image

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail
from wgpurender.core.files.imageio import check_png_complete
from wgpurender.core.files.input_files import check_image_pixels, input_file

MAX_DIM_LIMIT = "max-texture-dimension-2d"
_EIGHT_BIT_MODES = {"1", "L", "LA", "La", "P", "PA", "RGB", "RGBA", "RGBa", "RGBX", "CMYK", "YCbCr", "LAB", "HSV"}
_SIXTEEN_BIT_MODES = {"I;16", "I;16L", "I;16B", "I;16N"}

# ---------------------------------------------------------------------------
# Pixels: files and arrays to (H, W, 4) uint8
# ---------------------------------------------------------------------------


def _too_large(what: str, width: int, height: int, max_dim: int) -> UserError:
    return UserError(
        f"{what} is {width}x{height}, larger than this GPU's {MAX_DIM_LIMIT} limit of {max_dim}: "
        f"resize it to at most {max_dim} pixels on each side"
    )


def _check_dims(what: str, width: int, height: int, max_dim: int | None) -> None:
    if width < 1 or height < 1:
        raise UserError(f"{what} is empty ({width}x{height}): a texture needs at least 1x1 pixels")
    if max_dim is not None and max(width, height) > max_dim:
        raise _too_large(what, width, height, max_dim)


def _sixteen_to_eight(values: np.ndarray, what: str) -> np.ndarray:
    """The documented 16 -> 8 bit rule: keep the high byte."""
    values = np.asarray(values)
    if values.size and (values.min() < 0 or values.max() > 0xFFFF):
        raise UserError(f"{what} holds values outside 0..65535: only 8- and 16-bit images can become textures")
    return (values.astype(np.uint32) >> 8).astype(np.uint8)


def _expand_channels(pixels: np.ndarray, what: str) -> np.ndarray:
    """(H, W) or (H, W, 1..4) uint8 -> (H, W, 4): grey to RGB, missing alpha = 255."""
    if pixels.ndim == 2:
        pixels = pixels[..., None]
    if pixels.ndim != 3 or not 1 <= pixels.shape[2] <= 4:
        raise UserError(f"{what} has shape {pixels.shape}: expected (H, W) or (H, W, C) with C = 1..4 channels")
    h, w, c = pixels.shape
    out = np.empty((h, w, 4), dtype=np.uint8)
    grey = c in (1, 2)
    out[..., :3] = pixels[..., :1] if grey else pixels[..., :3]
    out[..., 3] = pixels[..., c - 1] if c in (2, 4) else 255
    return out


def pixels_from_array(array: np.ndarray, *, max_dim: int | None = None) -> np.ndarray:
    """A numpy image as (H, W, 4) uint8 by the rules in the module docstring."""
    what = "texture array"
    arr = np.asarray(array)
    if arr.ndim not in (2, 3):
        raise UserError(f"{what} has shape {arr.shape}: expected (H, W) or (H, W, C) with C = 1..4 channels")
    _check_dims(what, arr.shape[1], arr.shape[0], max_dim)
    if arr.dtype == np.uint8:
        pass
    elif arr.dtype == np.uint16:
        arr = _sixteen_to_eight(arr, what)
    elif np.issubdtype(arr.dtype, np.floating):
        if not np.all(np.isfinite(arr)) or arr.min() < 0.0 or arr.max() > 1.0:
            raise UserError(f"{what} of floats must hold finite values in [0, 1] (got {arr.min()}..{arr.max()})")
        arr = np.round(arr.astype(np.float64) * 255.0).astype(np.uint8)
    else:
        raise UserError(f"{what} has dtype {arr.dtype}: use uint8, uint16 or floats in [0, 1]")
    return np.ascontiguousarray(_expand_channels(arr, what))


def load_image(path: str | os.PathLike, *, max_dim: int | None = None) -> np.ndarray:
    """Read a PNG/JPEG (anything Pillow reads) as (H, W, 4) uint8.

    The size is checked from the header, before any pixel is decoded, so an image
    too large for the GPU fails fast and without allocating it.
    """
    path = Path(path)
    try:
        with _embedded_or_file(path) as source, Image.open(source) as im:
            _check_dims(f"image {path}", im.width, im.height, max_dim)
            check_image_pixels(im.width, im.height, str(path))
            check_png_complete(source, str(path))
            im.load()
            return _image_to_rgba8(im, path)
    except Image.DecompressionBombError as err:
        limit = f"; the GPU's {MAX_DIM_LIMIT} is {max_dim}" if max_dim else ""
        raise UserError(f"image {path} is too large to decode safely ({err}){limit}") from None
    except (OSError, ValueError, SyntaxError) as err:
        raise UserError(f"cannot read image {path}: {err} (is it a valid PNG or JPEG file?)") from None


def _embedded_or_file(path: Path):
    """What Pillow opens: the file (opened through the read jail: the file checked when the scene loaded), or the
    bytes of an image embedded in a glTF model (``model.glb#images[k]``, see gltf_materials.embedded_image_path)."""
    if not os.path.lexists(path):
        from wgpurender.core.scene.gltf_materials import embedded_image_bytes

        data = embedded_image_bytes(path, decode=load_image)
        if data is not None:
            import io

            return io.BytesIO(data)
    found = input_file(path, "texture image", f"texture image not found: {path} (check the path)")
    return read_jail.open_checked(found)


def _image_to_rgba8(im: Image.Image, path: Path) -> np.ndarray:
    mode = im.mode
    what = f"image {path}"
    if mode in _EIGHT_BIT_MODES:
        return np.ascontiguousarray(np.asarray(im.convert("RGBA")))
    if mode in _SIXTEEN_BIT_MODES or mode == "I":
        values = np.asarray(im)  # I;16* -> uint16, I -> int32
        if mode == "I" and values.size and (values.min() < 0 or values.max() > 0xFFFF):
            raise UserError(f"{what} is a 32-bit integer image with values outside 0..65535: save it as 8 or 16 bit")
        return _expand_channels(_sixteen_to_eight(values, what), what)
    raise UserError(
        f"{what} has pixel mode {mode!r}, which cannot become an RGBA8 texture: save it as 8- or 16-bit RGB(A) or grey"
    )


def image_pixels(source, *, max_dim: int | None = None) -> np.ndarray:
    """A path or a numpy array as (H, W, 4) uint8."""
    if isinstance(source, np.ndarray):
        return pixels_from_array(source, max_dim=max_dim)
    if isinstance(source, (str, os.PathLike)):
        return load_image(source, max_dim=max_dim)
    raise UserError(f"a texture comes from an image path or a numpy array, not {type(source).__name__}")


def image_size(path: str | os.PathLike) -> tuple[int, int] | None:
    """(width, height) from an image file's header (no pixel decoded); None when it cannot be read
    (the upload then says why, with :func:`load_image`'s message)."""
    try:
        with _embedded_or_file(Path(path)) as source, Image.open(source) as im:
            return im.width, im.height
    except (OSError, ValueError, SyntaxError, Image.DecompressionBombError, UserError):
        return None


def mip_level_count(width: int, height: int) -> int:
    """Levels down to 1x1: floor(log2(max side)) + 1."""
    return max(width, height).bit_length()


def mip_size(width: int, height: int, level: int) -> tuple[int, int]:
    """Size of a level: each side max(1, side >> level), as Vulkan and WebGPU define it."""
    return max(1, width >> level), max(1, height >> level)
