"""Radiance RGBE (.hdr) images: the equirectangular environments of image-based lighting.

The format (Greg Ward's, as ``radiance/src/common/color.c`` writes it): text header lines ending in an empty
line (``#?RADIANCE`` or ``#?RGBE`` first, ``FORMAT=32-bit_rle_rgbe``), a resolution line ``-Y H +X W`` (rows
top to bottom, the only orientation accepted), then H scanlines of W pixels of 4 bytes (R, G, B, shared
exponent E: value = (byte + 0.5) / 256 * 2^(E - 128), 0 when E = 0). A scanline is flat, or (8 <= W < 32768)
"new" run-length encoded: 2, 2, W >> 8, W & 255, then each of the four channels in turn as runs (a count
above 128: the next byte repeated count - 128 times) and dumps (count bytes copied).

Bounded like every image input: the file's bytes and the declared pixel count are checked before decoding
(core/files/input_files.py), and every malformed or truncated file is refused in one line naming the file.
"""

from __future__ import annotations

import os

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.input_files import check_file_size, check_image_pixels, input_file
from wgpurender.core.files.read_jail import read_checked

MAX_HEADER_LINES = 64


def load_hdr(path: str | os.PathLike) -> np.ndarray:
    """(height, width, 3) float32 linear radiance of a Radiance .hdr file."""
    path = input_file(path, "environment image")
    check_file_size(path, "environment image")
    data = read_checked(path)  # the file the scene's check let through, not one swapped in since
    try:
        return decode_hdr(data, path.name)
    except (IndexError, ValueError):
        raise UserError(f"environment image {path.name}: truncated or malformed Radiance .hdr data; "
                        "write it again as Radiance RGBE (.hdr)") from None


def _header(data: bytes, name: str) -> tuple[int, int, int]:
    """(height, width, offset of the first scanline)."""
    pos, lines = 0, []
    for _ in range(MAX_HEADER_LINES + 2):
        end = data.index(b"\n", pos)
        lines.append(data[pos:end].strip())
        pos = end + 1
        if lines[0] not in (b"#?RADIANCE", b"#?RGBE"):
            raise UserError(f"environment image {name}: not a Radiance .hdr file (it must start with #?RADIANCE)")
        if len(lines) > 1 and lines[-1] == b"":
            break
    else:
        raise UserError(f"environment image {name}: header longer than {MAX_HEADER_LINES} lines: not a Radiance .hdr")
    formats = [line[7:] for line in lines if line.startswith(b"FORMAT=")]
    if formats and formats[0] != b"32-bit_rle_rgbe":
        raise UserError(f"environment image {name}: FORMAT={formats[0].decode(errors='replace')} is not "
                        "supported (only 32-bit_rle_rgbe)")
    end = data.index(b"\n", pos)
    parts = data[pos:end].split()
    if len(parts) != 4 or parts[0] != b"-Y" or parts[2] != b"+X" or not parts[1].isdigit() or not parts[3].isdigit():
        raise UserError(f"environment image {name}: resolution line {data[pos:end][:40]!r} is not '-Y H +X W' "
                        "(the only orientation supported)")
    height, width = int(parts[1]), int(parts[3])
    if height < 1 or width < 1:
        raise UserError(f"environment image {name}: {width}x{height} pixels: an image needs at least one")
    check_image_pixels(width, height, name)
    return height, width, end + 1


def _rle_line(data: bytes, pos: int, width: int) -> tuple[np.ndarray, int]:
    """One new-style RLE scanline (the 4 bytes 2, 2, hi, lo already checked at ``pos``)."""
    line = np.empty((4, width), np.uint8)
    pos += 4
    for channel in range(4):
        x = 0
        while x < width:
            count = data[pos]
            if count > 128:
                count -= 128
                if x + count > width:
                    raise ValueError("run past the scanline")
                line[channel, x:x + count] = data[pos + 1]
                pos += 2
            else:
                if count == 0 or x + count > width or pos + 1 + count > len(data):
                    raise ValueError("bad dump")
                line[channel, x:x + count] = np.frombuffer(data, np.uint8, count, pos + 1)
                pos += 1 + count
            x += count
    return line.T, pos


def decode_hdr(data: bytes, name: str = "<hdr>") -> np.ndarray:
    height, width, pos = _header(data, name)
    rgbe = np.empty((height, width, 4), np.uint8)
    for y in range(height):
        head = data[pos:pos + 4]
        if 8 <= width < 32768 and len(head) == 4 and head[0] == 2 and head[1] == 2 and not head[2] & 0x80:
            if (head[2] << 8 | head[3]) != width:
                raise UserError(f"environment image {name}: scanline {y} says width {head[2] << 8 | head[3]}, "
                                f"the header {width}")
            rgbe[y], pos = _rle_line(data, pos, width)
        else:
            if pos + 4 * width > len(data):
                raise ValueError("truncated")
            rgbe[y] = np.frombuffer(data, np.uint8, 4 * width, pos).reshape(width, 4)
            pos += 4 * width
    e = rgbe[..., 3].astype(np.int32)
    scale = np.where(e > 0, np.ldexp(1.0, e - 136), 0.0)  # 2^(E - 128) / 256
    return ((rgbe[..., :3] + 0.5) * scale[..., None]).astype(np.float32)


def encode_hdr(radiance: np.ndarray) -> bytes:
    """A flat (not run-length encoded) Radiance .hdr of (h, w, 3) radiance: for tests and generated assets."""
    rgb = np.maximum(np.asarray(radiance, np.float64), 0.0)
    peak = rgb.max(axis=-1)
    mantissa, exponent = np.frexp(peak)
    scale = np.where(peak > 1e-32, mantissa * 256.0 / np.where(peak > 1e-32, peak, 1.0), 0.0)
    out = np.zeros(rgb.shape[:2] + (4,), np.uint8)
    out[..., :3] = np.clip(np.floor(rgb * scale[..., None]), 0, 255)
    out[..., 3] = np.where(peak > 1e-32, exponent + 128, 0)
    h, w = rgb.shape[:2]
    return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w) + out.tobytes()
