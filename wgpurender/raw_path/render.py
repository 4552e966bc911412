"""Headless rendering on the raw-Vulkan path: a stage into an image, copied back into numpy."""

from __future__ import annotations

from contextlib import ExitStack

import numpy as np
import vulkan as vk

from wgpurender.core.course.formats import is_scene_file
from wgpurender.core.errors import UserError
from wgpurender.core.plan import gpu_memory
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.raw_path.device.checks import check_msaa, check_size
from wgpurender.raw_path.device.command_buffers import one_shot
from wgpurender.raw_path.device.context import get_vulkan
from wgpurender.raw_path.device.images import FORMATS, Image, create_image, subresource_range, transition
from wgpurender.raw_path.device.readback import buffer_to_pixels, record_copy_to_buffer
from wgpurender.raw_path.stages import get_ref_stage
from wgpurender.raw_path.stages.base import TARGET_LAYOUT, TARGET_USAGE

__all__ = ["check_msaa", "check_size", "render_reference"]

def render_reference(
    stage: str,
    size: tuple[int, int] | None = (800, 600),
    fmt: str | None = None,
    msaa: int | None = None,
    t: float = 0.0,
    anisotropy: str = DEFAULT_ANISOTROPY,
) -> np.ndarray:
    """Render one stage (or a scene file, ``*.toml``: size None = its [render] size) with raw Vulkan calls
    and return its pixels, (H, W, 4).

    uint8 for the 8-bit formats (stored bytes: sRGB-encoded for rgba8unorm-srgb),
    float16 for rgba16float, like wgpurender.wgpu_path.render.render_stage. Everything made
    for the render is destroyed before returning. With validation on, any
    validation message raises ValidationFailed.
    """
    if is_scene_file(stage):  # a scene file: the final scene, drawn by raw_path/scene/
        from wgpurender.raw_path.scene import render_scene_reference

        return render_scene_reference(stage, size=size, fmt=fmt, msaa=msaa, t=t, anisotropy=anisotropy)
    return render_stage_class(get_ref_stage(stage), size or (800, 600), fmt, msaa, t)


def render_stage_class(cls: type, size: tuple[int, int], fmt: str | None = None, msaa: int | None = None,
                       t: float = 0.0) -> np.ndarray:
    """Render one RefStage subclass (a registered one, or a learner's: wgpurender/exercises/) headless."""
    stage = cls.name
    fmt = fmt or cls.default_format
    if fmt not in FORMATS:
        raise UserError(f"unsupported colour format {fmt!r}: choose one of {', '.join(FORMATS)}")
    ctx = get_vulkan()
    msaa = check_msaa(ctx, cls, msaa)
    size = check_size(ctx, size)
    gpu_memory.check_memory(gpu_memory.stage_textures(size, fmt, msaa), ctx.device_type,
                            f"stage {stage} at {size[0]}x{size[1]}, msaa {msaa}")
    with ExitStack() as owned:
        ref_stage = cls(ctx, owned, fmt, msaa, size)
        target = create_image(ctx, owned, size, fmt, TARGET_USAGE)
        zero(ctx, target)
        with one_shot(ctx) as cmd:
            ref_stage.record(cmd, target, t)
            buffer = record_copy_to_buffer(ctx, owned, cmd, target)
        pixels = buffer_to_pixels(ctx, buffer, target)
    ctx.check_validation(f"the raw-Vulkan render of {stage!r}")
    return pixels


def zero(ctx, target: Image) -> None:
    """Clear the fresh target to zeros in a submission of its own, before the stage records; it is left in
    TARGET_LAYOUT, the layout a stage's first barrier names as the old one (stages/base.py).

    Vulkan leaves new image memory undefined; lavapipe hands back freed memory, which may still hold the previous
    render. A stage that writes only part of its target (a learner's 1x1 copy, wgpurender/exercises/) would then
    show the previous image where it wrote nothing, and pass. wgpu zero-initialises textures: this gives the raw
    path the same start, so unwritten pixels read (0, 0, 0, 0) on both paths. By the spec, not by the driver's
    habit: the stage's barriers start from this layout, never from UNDEFINED (which may discard the contents).
    """
    with one_shot(ctx) as cmd:
        transition(cmd, target, vk.VK_IMAGE_LAYOUT_UNDEFINED, TARGET_LAYOUT)
        zeros = vk.VkClearColorValue(float32=[0.0, 0.0, 0.0, 0.0])
        vk.vkCmdClearColorImage(cmd, target.handle, TARGET_LAYOUT, zeros, 1, [subresource_range()])
