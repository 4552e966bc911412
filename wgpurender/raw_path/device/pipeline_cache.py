"""The VkPipelineCache: loaded from ~/.cache/wgpurender/ when the device is created, saved when it closes.

The file name carries the vendor, device and pipeline-cache UUID, so a driver never sees another
device's data. ``ctx`` is the VulkanContext being created or closed (instance.py calls these; this
module does not import it, which would be a cycle).
"""

from __future__ import annotations

import vulkan as vk

from wgpurender.raw_path.device.shaders import cache_dir


def pipeline_cache_path(props) -> object:
    uuid = bytes(list(props.pipelineCacheUUID)).hex()
    return cache_dir().parent / f"vk-pipeline-cache-{props.vendorID:04x}-{props.deviceID:04x}-{uuid}.bin"


def create_pipeline_cache(ctx, props):
    """vkCreatePipelineCache seeded with the data saved by the last run on this device, if any."""
    path = pipeline_cache_path(props)
    ctx.pipeline_cache_file = path
    data = path.read_bytes() if path.is_file() else b""
    initial = vk.ffi.from_buffer(data) if data else None
    info = vk.VkPipelineCacheCreateInfo(initialDataSize=len(data), pInitialData=initial)
    return vk.vkCreatePipelineCache(ctx.device, info, None)


def save_pipeline_cache(ctx) -> None:
    """vkGetPipelineCacheData (the binding does not wrap it: two calls through the raw library, size then data)."""
    size = vk.ffi.new("size_t *")
    if vk.lib.vkGetPipelineCacheData(ctx.device, ctx.pipeline_cache, size, vk.ffi.NULL) != vk.VK_SUCCESS:
        return
    data = vk.ffi.new("char[]", size[0])
    if vk.lib.vkGetPipelineCacheData(ctx.device, ctx.pipeline_cache, size, data) != vk.VK_SUCCESS:
        return
    path = ctx.pipeline_cache_file
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp")
        tmp.write_bytes(vk.ffi.buffer(data, size[0]))
        tmp.replace(path)
    except OSError:
        pass  # a cache that cannot be written only costs time on the next run
