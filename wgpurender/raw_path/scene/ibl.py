"""Image-based lighting maps made on the GPU in raw Vulkan compute (shaders_glsl/ibl.comp, the GLSL twin of
shaders_wgsl/ibl.wgsl): the irradiance map, the prefiltered levels and the split-sum BRDF table, in the texel
layout of core/course/ibl_maps.py (which makes the same maps in float64 to check these against).

Course concepts: compute pipelines (vkCreateComputePipelines, one shader stage, no render pass), storage buffers
as descriptors, vkCmdDispatch in workgroups of 8x8, and a pipeline barrier that makes the shader's writes
visible to the host before the buffers are mapped.
"""

from __future__ import annotations

from contextlib import ExitStack

import numpy as np
import vulkan as vk

from wgpurender.core.course.ibl_maps import (
    IRRADIANCE_SIZE,
    LEVELS,
    LUT_SIZE,
    PREFILTER_SIZE,
    IblArrays,
    packed_bytes,
    packed_regions,
    pass_sizes,
    regions,
)
from wgpurender.raw_path.device import descriptors
from wgpurender.raw_path.device.command_buffers import one_shot
from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.memory import HOST_MEMORY, create_buffer, read_host_buffer, write_host_buffer
from wgpurender.raw_path.device.pipeline import create_pipeline_layout
from wgpurender.raw_path.device.shaders import create_shader_module

SHADER = "ibl.comp"
WORKGROUP = 8
COMPUTE = vk.VK_SHADER_STAGE_COMPUTE_BIT
STORAGE = vk.VK_DESCRIPTOR_TYPE_STORAGE_BUFFER
BINDINGS = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, COMPUTE),
            descriptors.binding(1, STORAGE, COMPUTE), descriptors.binding(2, STORAGE, COMPUTE)]


def _host_buffer(ctx: VulkanContext, owned: ExitStack, size: int, usage: int, data: bytes | None = None):
    buffer = create_buffer(ctx, owned, size, usage, HOST_MEMORY)
    if data is not None:
        write_host_buffer(ctx, buffer, data)
    return buffer


def _compute_pipeline(ctx: VulkanContext, owned: ExitStack, layout, define: str):
    """vkCreateComputePipelines: the one stage of ibl.comp built with -D``define`` (a pass's name in capitals)."""
    module = create_shader_module(ctx.device, SHADER, (define,))
    owned.callback(vk.vkDestroyShaderModule, ctx.device, module, None)
    stage = vk.VkPipelineShaderStageCreateInfo(stage=COMPUTE, module=module, pName="main")
    info = vk.VkComputePipelineCreateInfo(stage=stage, layout=layout, basePipelineIndex=-1)
    pipeline = vk.vkCreateComputePipelines(ctx.device, ctx.pipeline_cache, 1, [info], None)[0]
    owned.callback(vk.vkDestroyPipeline, ctx.device, pipeline, None)
    return pipeline


def _record(ctx: VulkanContext, owned: ExitStack, environment: np.ndarray, samples: int, passes, out) -> None:
    """Dispatch the passes into their regions of ``out`` (a host-visible storage buffer) and wait; the barrier
    makes the shader's writes visible to the host, whether it maps them or the scene's draws read them."""
    h, w = environment.shape[:2]
    rgba = np.concatenate([environment, np.ones((h, w, 1))], axis=-1).astype(np.float32)
    env = _host_buffer(ctx, owned, rgba.nbytes, vk.VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, rgba.tobytes())
    set_layout = descriptors.create_set_layout(ctx, owned, BINDINGS)
    layout = create_pipeline_layout(ctx, owned, [set_layout])
    pool = descriptors.create_pool(ctx, owned, [BINDINGS] * len(passes))
    sets = descriptors.allocate_sets(ctx, pool, [set_layout] * len(passes))
    offsets, _ = regions(passes)
    with one_shot(ctx) as cmd:
        for (define, (ow, oh), depth), dst_set, offset in zip(passes, sets, offsets, strict=True):
            params = np.array([w, h, ow, oh, samples, depth, 0, 0], np.uint32).tobytes()
            uniform = _host_buffer(ctx, owned, len(params), vk.VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, params)
            writes = [descriptors.write_buffer(dst_set, 0, uniform.handle, 0, uniform.size),
                      descriptors.write_buffer(dst_set, 1, env.handle, 0, env.size, STORAGE),
                      descriptors.write_buffer(dst_set, 2, out.handle, offset, 16 * ow * oh * depth, STORAGE)]
            descriptors.update(ctx, writes)
            vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_COMPUTE,
                                 _compute_pipeline(ctx, owned, layout, define.upper()))
            vk.vkCmdBindDescriptorSets(cmd, vk.VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, [dst_set], 0, None)
            vk.vkCmdDispatch(cmd, -(-ow // WORKGROUP), -(-oh // WORKGROUP), depth)
        visible = vk.VkMemoryBarrier(srcAccessMask=vk.VK_ACCESS_SHADER_WRITE_BIT,
                                     dstAccessMask=vk.VK_ACCESS_HOST_READ_BIT | vk.VK_ACCESS_SHADER_READ_BIT)
        vk.vkCmdPipelineBarrier(cmd, vk.VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                vk.VK_PIPELINE_STAGE_HOST_BIT | vk.VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0,
                                1, [visible], 0, None, 0, None)
    ctx.check_validation("image-based lighting maps (compute)")


def scene_maps_buffer(ctx: VulkanContext, owned: ExitStack, environment: np.ndarray, samples: int):
    """The scene's maps made straight into one host-visible storage buffer in core/course/ibl_maps.py's packed
    layout (each pass its region, as the wgpu path's scene_maps_buffer does); it lives as long as ``owned``."""
    packed_regions()  # the packed layout's regions start where a storage binding may (the core's rule)
    out = _host_buffer(ctx, owned, packed_bytes(), vk.VK_BUFFER_USAGE_STORAGE_BUFFER_BIT)
    with ExitStack() as transient:  # the pipelines, sets and inputs: gone once the maps are made
        _record(ctx, transient, environment, samples, pass_sizes(), out)
    return out


def make_maps(ctx: VulkanContext, environment: np.ndarray, samples: int, levels: int = LEVELS,
              irradiance_size=IRRADIANCE_SIZE, prefilter_size=PREFILTER_SIZE, lut_size: int = LUT_SIZE) -> IblArrays:
    """The three maps of ``environment`` ((h, w, 3) linear float), read back (as wgpu_path/scene/ibl.make_maps)."""
    passes = [("irradiance", irradiance_size, 1), ("prefilter", prefilter_size, levels),
              ("brdf_lut", (lut_size, lut_size), 1)]
    offsets, size = regions(passes)  # padded to the core's alignment where these sizes need it
    with ExitStack() as owned:
        out = _host_buffer(ctx, owned, size, vk.VK_BUFFER_USAGE_STORAGE_BUFFER_BIT)
        _record(ctx, owned, environment, samples, passes, out)
        data = read_host_buffer(ctx, out).view(np.float32)
    irr, pre, lut = (data[o // 4:o // 4 + 4 * ow * oh * d].reshape(-1, 4)
                     for o, (_, (ow, oh), d) in zip(offsets, passes, strict=True))
    (iw, ih), (pw, ph) = irradiance_size, prefilter_size
    return IblArrays(irr.reshape(ih, iw, 4)[..., :3], pre.reshape(levels, ph, pw, 4)[..., :3],
                     lut.reshape(lut_size, lut_size, 4)[..., :2])
