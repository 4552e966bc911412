"""wgpu-native calls that wgpu-py 0.32 does not wrap, reached through its cffi handle.

Kept in one module so that the day wgpu-py wraps them, one file changes; the reach itself (the native library and
the objects' handles) is wgpu_private.py's.
"""

from __future__ import annotations

import wgpu

from wgpurender.core.errors import UserError
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.wgpu_private import handle, native, surface_handle


def clear_texture(ctx: GPUContext, encoder: wgpu.GPUCommandEncoder, texture: wgpu.GPUTexture) -> None:
    """Record wgpuCommandEncoderClearTexture: every texel of every mip becomes zero.

    This is a transfer command outside any render pass, like vkCmdClearColorImage;
    unlike it, WebGPU's clear has no colour argument: it always writes zeros.
    """
    if not ctx.has("clear-texture"):
        raise UserError("this adapter lacks the 'clear-texture' feature: use the stage 'clear-pass' instead")
    ffi, lib = native()
    subresources = ffi.new(
        "WGPUImageSubresourceRange *",
        {
            "aspect": lib.WGPUTextureAspect_All,
            "baseMipLevel": 0,
            "mipLevelCount": texture.mip_level_count,
            "baseArrayLayer": 0,
            "arrayLayerCount": texture.size[2],
        },
    )
    lib.wgpuCommandEncoderClearTexture(handle(encoder), handle(texture), subresources)


def timestamp_period_ns(ctx: GPUContext) -> float:
    """Nanoseconds per timestamp tick (wgpuQueueGetTimestampPeriod; VkPhysicalDeviceLimits::timestampPeriod).
    Dawn resolves timestamps in nanoseconds already, as WebGPU specifies (and has no such function): 1."""
    from wgpurender.wgpu_path import binding

    if binding.name() == "dawn":
        return 1.0
    _, lib = native()
    return float(lib.wgpuQueueGetTimestampPeriod(handle(ctx.queue)))



def surface_supports(context, adapter) -> bool:
    """Whether a window's surface can present frames of ``adapter`` (wgpuSurfaceGetCapabilities gives no formats
    when it cannot). wgpu-py 0.32 hides that answer (it substitutes a minimal format list), and configuring such a
    surface aborts the process in wgpu-native; True when the surface is not made yet (nothing to ask)."""
    ffi, lib = native()
    surface_id = surface_handle(context)
    if not surface_id:
        return True
    caps = ffi.new("WGPUSurfaceCapabilities *")
    if lib.wgpuSurfaceGetCapabilities(surface_id, handle(adapter), caps) != lib.WGPUStatus_Success:
        return False
    supported = caps.formats != ffi.NULL and caps.formatCount > 0
    lib.wgpuSurfaceCapabilitiesFreeMembers(caps[0])
    return supported
