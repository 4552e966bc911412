"""Offscreen colour targets and their readback into numpy.

The course renders into a VkImage that is not the swapchain, then copies it into a
host-visible buffer with vkCmdCopyImageToBuffer and maps it. wgpu does the same
with ``copy_texture_to_buffer``; the one trap is that each row in the buffer must
start at a multiple of 256 bytes, so rows are padded on the GPU and unpadded here.
"""

from __future__ import annotations

import numpy as np
import wgpu

from .course.formats import OUTPUT_FORMATS
from .errors import UserError
from .gpu import GPUContext

ROW_ALIGNMENT = 256

# format -> (bytes per pixel, numpy dtype of one channel)
COLOR_FORMATS: dict[str, tuple[int, type]] = {
    "rgba8unorm": (4, np.uint8),
    "rgba8unorm-srgb": (4, np.uint8),
    "bgra8unorm": (4, np.uint8),
    "bgra8unorm-srgb": (4, np.uint8),
    "rgba16float": (8, np.float16),
    "rgba32float": (16, np.float32),
}

TARGET_USAGE = (
    wgpu.TextureUsage.RENDER_ATTACHMENT
    | wgpu.TextureUsage.COPY_SRC
    | wgpu.TextureUsage.COPY_DST
    | wgpu.TextureUsage.TEXTURE_BINDING
)


def check_format(fmt: str) -> str:
    if fmt not in COLOR_FORMATS:
        raise UserError(f"unsupported colour format {fmt!r}: choose one of {', '.join(OUTPUT_FORMATS)}")
    return fmt


def padded_bytes_per_row(width: int, bytes_per_pixel: int) -> int:
    """Row pitch rounded up to the 256-byte alignment copies need."""
    unpadded = width * bytes_per_pixel
    return (unpadded + ROW_ALIGNMENT - 1) // ROW_ALIGNMENT * ROW_ALIGNMENT


def create_target(
    ctx: GPUContext,
    size: tuple[int, int],
    fmt: str = "rgba8unorm-srgb",
    *,
    sample_count: int = 1,
    usage: int = TARGET_USAGE,
    label: str = "target",
) -> wgpu.GPUTexture:
    """A 2D colour texture to render into (the offscreen VkImage + memory)."""
    check_format(fmt)
    if sample_count > 1:
        usage = wgpu.TextureUsage.RENDER_ATTACHMENT  # multisampled images are never copied
    return ctx.device.create_texture(
        label=label,
        size=(size[0], size[1], 1),
        format=fmt,
        usage=usage,
        sample_count=sample_count,
    )


def read_texture(ctx: GPUContext, texture: wgpu.GPUTexture, level: int = 0) -> np.ndarray:
    """Copy one mip level of a single-sample colour texture to the host as an (H, W, 4) array.

    uint8 for 8-bit formats (raw stored bytes, so sRGB formats give sRGB-encoded
    values), float16/float32 for float formats. Blocks until the GPU is done.
    """
    fmt = texture.format
    bpp, dtype = COLOR_FORMATS[check_format(fmt)]
    width, height = max(1, texture.size[0] >> level), max(1, texture.size[1] >> level)
    pitch = padded_bytes_per_row(width, bpp)
    buffer = ctx.device.create_buffer(
        size=pitch * height, usage=wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.MAP_READ, label="readback"
    )
    encoder = ctx.device.create_command_encoder(label="readback")
    encoder.copy_texture_to_buffer(
        {"texture": texture, "mip_level": level, "origin": (0, 0, 0)},
        {"buffer": buffer, "offset": 0, "bytes_per_row": pitch, "rows_per_image": height},
        (width, height, 1),
    )
    ctx.queue.submit([encoder.finish()])
    buffer.map_sync(wgpu.MapMode.READ)
    # copy=False: a view of the mapping, copied once (unpadded) before unmap; read_mapped's own copy cost 3-6x more
    raw = np.frombuffer(buffer.read_mapped(copy=False), dtype=np.uint8).reshape(height, pitch)
    pixels = raw[:, : width * bpp].copy().view(dtype).reshape(height, width, 4)
    del raw
    buffer.unmap()
    buffer.destroy()
    if fmt.startswith("bgra"):
        pixels = pixels[..., [2, 1, 0, 3]]
    return pixels
