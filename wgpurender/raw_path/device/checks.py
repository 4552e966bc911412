"""Checks of a raw-Vulkan render's size and sample count against the device, before anything is made."""

from __future__ import annotations

from wgpurender.core.course.formats import SAMPLE_COUNTS
from wgpurender.core.errors import UserError
from wgpurender.raw_path.device.context import VulkanContext


def check_msaa(ctx: VulkanContext, cls, msaa: int | None) -> int:
    """The sample count for a stage class: its default, or ``msaa`` if the stage and the device take it."""
    msaa = cls.default_msaa if msaa is None else msaa
    supported = [n for n in SAMPLE_COUNTS if ctx.limits.framebuffer_color_sample_counts & n]
    if msaa not in supported:
        raise UserError(f"MSAA {msaa}x is not supported by {ctx.device_name}: supported sample counts are "
                        f"{', '.join(map(str, supported))}")
    if msaa > 1 and not cls.supports_msaa:
        raise UserError(f"stage {cls.name!r} does not use MSAA: leave out --msaa")
    return msaa


def check_size(ctx: VulkanContext, size: tuple[int, int]) -> tuple[int, int]:
    width, height = (int(v) for v in size)
    limit = ctx.limits.max_image_dimension_2d
    if not (0 < width <= limit and 0 < height <= limit):
        raise UserError(f"image size {width}x{height} out of range: width and height must be 1..{limit}")
    return width, height
