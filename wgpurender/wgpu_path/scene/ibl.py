"""Image-based lighting maps made on the GPU (shaders_wgsl/ibl.wgsl's compute passes): the irradiance map, the
prefiltered specular levels by roughness and the split-sum BRDF lookup table, from an equirectangular
environment (wgpurender/core/course/environment.py). Storage buffers in, storage buffers out, read back as float32.

Scenes with an [environment] draw with them: scene_maps_buffer() makes them straight into the scene's storage
buffer in core/course/ibl_maps.py's packed layout, each pass writing its region (no readback; what it creates is
what the plan lists, core/plan/objects.py). raw_path/scene/ibl.py makes the same maps with shaders_glsl/ibl.comp,
the GLSL twin. ``bench accuracy --truth analytic`` times make_maps() and measures its error against a float64
integral.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import wgpu

from wgpurender.core.course.ibl_maps import (
    IRRADIANCE_SIZE,
    LEVELS,
    LUT_SIZE,
    PREFILTER_SIZE,
    packed_bytes,
    packed_regions,
    pass_sizes,
)
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module

SHADER = "ibl.wgsl"
WORKGROUP = 8


@dataclass
class IblMaps:
    irradiance: np.ndarray  # (h, w, 3) E / pi per normal direction
    prefiltered: np.ndarray  # (levels, h, w, 3), level k at roughness k / (levels - 1)
    lut: np.ndarray  # (n, n, 2): [roughness row, n.v column] -> (A, B)
    gpu_wall_ms: float  # encode, submit and wait for the three passes (readback excluded)


def _params(env_size, out_size, samples: int, levels: int) -> bytes:
    return np.array([*env_size, *out_size, samples, levels, 0, 0], np.uint32).tobytes()


def _pass(ctx: GPUContext, module, entry: str, params: bytes, env: wgpu.GPUBuffer, count: int,
          groups: tuple[int, int, int]) -> tuple[wgpu.GPUCommandBuffer, wgpu.GPUBuffer]:
    device = ctx.device
    uniform = device.create_buffer_with_data(data=params, usage=wgpu.BufferUsage.UNIFORM)
    out = device.create_buffer(size=16 * count, usage=wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_SRC)
    layout = device.create_bind_group_layout(entries=[
        {"binding": 0, "visibility": wgpu.ShaderStage.COMPUTE, "buffer": {"type": "uniform"}},
        {"binding": 1, "visibility": wgpu.ShaderStage.COMPUTE, "buffer": {"type": "read-only-storage"}},
        {"binding": 2, "visibility": wgpu.ShaderStage.COMPUTE, "buffer": {"type": "storage"}}])
    pipeline = device.create_compute_pipeline(
        label=f"ibl-{entry}", layout=device.create_pipeline_layout(bind_group_layouts=[layout]),
        compute={"module": module, "entry_point": entry})
    group = device.create_bind_group(layout=layout, entries=[
        {"binding": 0, "resource": {"buffer": uniform}}, {"binding": 1, "resource": {"buffer": env}},
        {"binding": 2, "resource": {"buffer": out}}])
    encoder = device.create_command_encoder(label=f"ibl-{entry}")
    compute = encoder.begin_compute_pass()
    compute.set_pipeline(pipeline)
    compute.set_bind_group(0, group)
    compute.dispatch_workgroups(*groups)
    compute.end()
    return encoder.finish(), out


def make_maps(ctx: GPUContext, environment: np.ndarray, samples: int, levels: int = LEVELS,
              irradiance_size=IRRADIANCE_SIZE, prefilter_size=PREFILTER_SIZE, lut_size: int = LUT_SIZE) -> IblMaps:
    """The three maps of ``environment`` ((h, w, 3) linear float) with ``samples`` GGX samples per texel."""
    h, w = environment.shape[:2]
    rgba = np.concatenate([environment, np.ones((h, w, 1))], axis=-1).astype(np.float32)
    env = ctx.device.create_buffer_with_data(data=rgba.tobytes(), usage=wgpu.BufferUsage.STORAGE)
    module = create_shader_module(ctx.device, SHADER)
    iw, ih = irradiance_size
    pw, ph = prefilter_size
    groups = lambda x, y, z=1: (-(-x // WORKGROUP), -(-y // WORKGROUP), z)  # noqa: E731
    start = time.perf_counter()
    passes = [_pass(ctx, module, "irradiance", _params((w, h), (iw, ih), samples, 1), env, iw * ih, groups(iw, ih)),
              _pass(ctx, module, "prefilter", _params((w, h), (pw, ph), samples, levels), env, pw * ph * levels,
                    groups(pw, ph, levels)),
              _pass(ctx, module, "brdf_lut", _params((w, h), (lut_size, lut_size), samples, 1), env,
                    lut_size * lut_size, groups(lut_size, lut_size))]
    ctx.device.queue.submit([command for command, _ in passes])
    ctx.wait_idle()
    wall = (time.perf_counter() - start) * 1e3
    irr, pre, lut = (np.frombuffer(ctx.read_buffer(out), np.float32).reshape(-1, 4) for _, out in passes)
    return IblMaps(irr.reshape(ih, iw, 4)[..., :3], pre.reshape(levels, ph, pw, 4)[..., :3],
                   lut.reshape(lut_size, lut_size, 4)[..., :2], wall)



PARAMS_STRIDE = 256  # one Params block per pass, at WebGPU's guaranteed minUniformBufferOffsetAlignment
STAGE = wgpu.ShaderStage.COMPUTE


def scene_maps_buffer(ctx: GPUContext, environment: np.ndarray, samples: int) -> wgpu.GPUBuffer:
    """The "scene-ibl" storage buffer: the three passes write their regions of it (at the packed layout's offsets,
    which the core checks start where a storage binding may: ibl_maps.packed_regions), in one command encoder,
    submitted once."""
    offsets = packed_regions()
    device = ctx.device
    h, w = environment.shape[:2]
    rgba = np.concatenate([environment, np.ones((h, w, 1))], axis=-1).astype(np.float32)
    env = device.create_buffer_with_data(data=rgba.tobytes(), usage=wgpu.BufferUsage.STORAGE,
                                         label="scene-ibl-environment")
    params = np.zeros((len(pass_sizes()), PARAMS_STRIDE // 4), np.uint32)
    for k, (_, (ow, oh), depth) in enumerate(pass_sizes()):
        params[k, :8] = [w, h, ow, oh, samples, depth, 0, 0]
    uniform = device.create_buffer_with_data(data=params.tobytes(), usage=wgpu.BufferUsage.UNIFORM,
                                             label="scene-ibl-params")
    maps = device.create_buffer(size=packed_bytes(), usage=wgpu.BufferUsage.STORAGE, label="scene-ibl")
    module = create_shader_module(device, SHADER)
    layout = device.create_bind_group_layout(entries=[
        {"binding": 0, "visibility": STAGE, "buffer": {"type": "uniform"}},
        {"binding": 1, "visibility": STAGE, "buffer": {"type": "read-only-storage"}},
        {"binding": 2, "visibility": STAGE, "buffer": {"type": "storage"}}], label="scene-ibl")
    pipeline_layout = device.create_pipeline_layout(bind_group_layouts=[layout], label="scene-ibl")
    encoder = device.create_command_encoder(label="scene-ibl")
    for k, (entry, (ow, oh), depth) in enumerate(pass_sizes()):
        size = 16 * ow * oh * depth
        pipeline = device.create_compute_pipeline(label=f"scene-ibl-{entry}", layout=pipeline_layout,
                                                  compute={"module": module, "entry_point": entry})
        group = device.create_bind_group(layout=layout, label=f"scene-ibl-{entry}", entries=[
            {"binding": 0, "resource": {"buffer": uniform, "offset": k * PARAMS_STRIDE, "size": 32}},
            {"binding": 1, "resource": {"buffer": env}},
            {"binding": 2, "resource": {"buffer": maps, "offset": offsets[k], "size": size}}])
        compute = encoder.begin_compute_pass()
        compute.set_pipeline(pipeline)
        compute.set_bind_group(0, group)
        compute.dispatch_workgroups(-(-ow // WORKGROUP), -(-oh // WORKGROUP), depth)
        compute.end()
    device.queue.submit([encoder.finish()])
    return maps
