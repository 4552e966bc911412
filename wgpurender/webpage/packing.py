"""How the recording's bytes travel in data.js: texture uploads and the reference frame as PNG, the rest base64.

A texture's pixels in base64 grew a page to 2.6-8.4 MB (brick's 237 KB of PNG became 4.2 MB). PNG is lossless
for any four bytes a texel (rgba8 colour, or the bytes of a float texture read as RGBA8), so every
``writeTexture`` blob whose rows are whole 4-byte texels, and the frame wgpu-native drew, go as PNG images of
their rows; the page decodes them to the exact bytes (player.js ``decodePng``: inflate with the browser's
DecompressionStream and undo the row filters; a canvas would premultiply alpha and change the bytes).
A blob is then either a base64 string (raw bytes) or ``{"png": base64, "bytes": length}``.
"""

from __future__ import annotations

import base64
import io

import numpy as np
from PIL import Image

TEXEL = 4


def png_base64(rgba: np.ndarray) -> str:
    """An (H, W, 4) uint8 array as a base64 PNG (8-bit RGBA, not interlaced)."""
    out = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(rgba, np.uint8), "RGBA").save(out, "PNG", compress_level=9)
    return base64.b64encode(out.getvalue()).decode("ascii")


def _texture_rows(calls: list[dict]) -> dict[int, int]:
    """blob index -> bytes per row, for the blobs uploaded by writeTexture."""
    rows = {}
    for call in calls:
        if call.get("m") == "writeTexture":
            data, layout = call["a"][1], call["a"][2]
            rows[data["#"]] = int(layout.get("bytesPerRow") or 0) if isinstance(layout, dict) else 0
    return rows


def pack_blobs(calls: list[dict], blobs: list[bytes]) -> list:
    """Each blob as data.js carries it: texture uploads whose rows are whole texels as PNG, the rest base64."""
    rows = _texture_rows(calls)
    out: list = []
    for index, data in enumerate(blobs):
        per_row = rows.get(index, 0)
        if per_row and per_row % TEXEL == 0 and len(data) % per_row == 0 and data:
            image = np.frombuffer(data, np.uint8).reshape(len(data) // per_row, per_row // TEXEL, TEXEL)
            out.append({"png": png_base64(image), "bytes": len(data)})
        else:
            out.append(base64.b64encode(data).decode("ascii"))
    return out
