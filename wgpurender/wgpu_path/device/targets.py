"""Offscreen colour targets and their readback into numpy.

The course renders into a VkImage that is not the swapchain, then copies it into a
host-visible buffer with vkCmdCopyImageToBuffer and maps it. wgpu does the same
with ``copy_texture_to_buffer``; the one trap is that each row in the buffer must
start at a multiple of 256 bytes, so rows are padded on the GPU and unpadded here.
"""

from __future__ import annotations

import numpy as np
import wgpu

from wgpurender.core.course.formats import OUTPUT_FORMATS
from wgpurender.core.errors import UserError
from wgpurender.wgpu_path.device.context import GPUContext

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


class Readback:
    """Copies of a colour texture to the host through one reused buffer: the raw path's way.

    ``record(encoder, texture)`` records the copy into the frame's own encoder (one submit per
    frame, like vkCmdCopyImageToBuffer in the frame's command buffer); after the submit,
    ``read()`` maps the buffer, unpads the rows and unmaps. The buffer grows when a larger
    texture comes and is otherwise kept, so a frame loop allocates nothing per frame.
    """

    def __init__(self, ctx: GPUContext) -> None:
        self.ctx = ctx
        self.buffer: wgpu.GPUBuffer | None = None
        self._pending: tuple[str, int, int, int, int, type] | None = None

    def record(self, encoder: wgpu.GPUCommandEncoder, texture: wgpu.GPUTexture, level: int = 0) -> None:
        fmt = texture.format
        bpp, dtype = COLOR_FORMATS[check_format(fmt)]
        width, height = max(1, texture.size[0] >> level), max(1, texture.size[1] >> level)
        pitch = padded_bytes_per_row(width, bpp)
        if self.buffer is None or self.buffer.size < pitch * height:
            if self.buffer is not None:
                self.buffer.destroy()
            self.buffer = self.ctx.device.create_buffer(
                size=pitch * height, usage=wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.MAP_READ, label="readback")
        encoder.copy_texture_to_buffer(
            {"texture": texture, "mip_level": level, "origin": (0, 0, 0)},
            {"buffer": self.buffer, "offset": 0, "bytes_per_row": pitch, "rows_per_image": height},
            (width, height, 1),
        )
        self._pending = (fmt, width, height, pitch, bpp, dtype)

    def read(self) -> np.ndarray:
        """The recorded copy as (H, W, 4) pixels; blocks until the GPU is done."""
        if self._pending is None:
            raise RuntimeError("Readback.read() before record()")
        fmt, width, height, pitch, bpp, dtype = self._pending
        self._pending = None
        self.ctx.map_read(self.buffer, 0, pitch * height)
        # copy=False: a view of the mapping, copied once (unpadded) before unmap; read_mapped's own copy cost 3-6x more
        raw = np.frombuffer(self.buffer.read_mapped(0, pitch * height, copy=False), dtype=np.uint8)
        pixels = raw.reshape(height, pitch)[:, : width * bpp].copy().view(dtype).reshape(height, width, 4)
        del raw
        self.buffer.unmap()
        if fmt.startswith("bgra"):
            pixels = pixels[..., [2, 1, 0, 3]]
        return pixels


def read_texture(ctx: GPUContext, texture: wgpu.GPUTexture, level: int = 0) -> np.ndarray:
    """Copy one mip level of a single-sample colour texture to the host as an (H, W, 4) array.

    uint8 for 8-bit formats (raw stored bytes, so sRGB formats give sRGB-encoded
    values), float16/float32 for float formats. Blocks until the GPU is done.
    A one-off :class:`Readback` (its own encoder, submit and buffer); frame loops keep one.
    """
    readback = Readback(ctx)
    encoder = ctx.device.create_command_encoder(label="readback")
    readback.record(encoder, texture, level)
    ctx.queue.submit([encoder.finish()])
    pixels = readback.read()
    readback.buffer.destroy()
    return pixels
