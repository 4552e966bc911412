"""The VkPipelineCache: loaded from ~/.cache/wgpurender/ when the device is created, saved when it closes.

The file name carries the vendor, device and pipeline-cache UUID, so a driver never sees another
device's data. The file is a verified cache entry (core/files/cache_entry.py) keyed by those and the driver version:
an empty, truncated or altered file, or one another driver wrote, is a miss (the driver starts with an empty
cache, the pipelines compile again, the same image); a driver never parses bytes nobody it trusts wrote.
``ctx`` is the VulkanContext being created or closed (instance.py calls these; this
module does not import it, which would be a cycle).
"""

from __future__ import annotations

import vulkan as vk

from wgpurender.core.files.cache_entry import read_entry, write_entry
from wgpurender.raw_path.device.shaders import cache_dir


def pipeline_cache_path(props) -> object:
    uuid = bytes(list(props.pipelineCacheUUID)).hex()
    return cache_dir().parent / f"vk-pipeline-cache-{props.vendorID:04x}-{props.deviceID:04x}-{uuid}.bin"


def pipeline_cache_key(props) -> str:
    uuid = bytes(list(props.pipelineCacheUUID)).hex()
    return (f"VkPipelineCache\0vendor {props.vendorID:#x}\0device {props.deviceID:#x}\0uuid {uuid}"
            f"\0driver {props.driverVersion:#x}\0api {props.apiVersion:#x}")


def create_pipeline_cache(ctx, props):
    """vkCreatePipelineCache seeded with the data saved by the last run on this device, if any."""
    path = pipeline_cache_path(props)
    ctx.pipeline_cache_file, ctx.pipeline_cache_key = path, pipeline_cache_key(props)
    data = read_entry(path, ctx.pipeline_cache_key) or b""
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
    write_entry(ctx.pipeline_cache_file, ctx.pipeline_cache_key, bytes(vk.ffi.buffer(data, size[0])))
    # (a cache that cannot be written only costs time on the next run)
