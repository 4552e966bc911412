"""Textures and samplers: images to RGBA8, upload, a gamma-correct mip chain on the GPU, cached samplers.

Course step 5. The course loads pixels on the CPU, copies them into a host-visible
staging buffer, records vkCmdCopyBufferToImage with layout transitions around it,
fills the mip levels with vkCmdBlitImage (one blit and barrier per level) and
creates a VkSampler. The wgpu analogue of each step is commented where it happens.

Pixel rules: wgpurender/core/scene/texture_pixels.py (API-free, shared with the raw path).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu

from wgpurender.core.course.samplers import (  # noqa: F401  (re-exported: the sampler vocabulary)
    ADDRESS_MODES,
    BILINEAR,
    FILTERS,
    MAX_ANISOTROPY,
    NEAREST,
    TRILINEAR,
    SamplerSpec,
    anisotropic,
)
from wgpurender.core.errors import UserError
from wgpurender.core.scene.texture_pixels import (  # noqa: F401  (re-exported: loading is part of this module's API)
    MAX_DIM_LIMIT,
    image_pixels,
    load_image,
    mip_level_count,
    mip_size,
    pixels_from_array,
)
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.gpu_cache import device_cache
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.device.targets import read_texture

SRGB_FORMAT = "rgba8unorm-srgb"  # colour textures: the sampler decodes to linear
LINEAR_FORMAT = "rgba8unorm"  # data textures (normal maps, roughness): values used as stored
TEXTURE_KINDS = {"color": True, "data": False}  # kind -> srgb

# ---------------------------------------------------------------------------
# Textures: upload and mip chain
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Texture:
    """An uploaded 2D texture and the view that samples all its levels."""

    texture: wgpu.GPUTexture
    view: wgpu.GPUTextureView
    size: tuple[int, int]
    format: str
    mip_level_count: int

    @property
    def srgb(self) -> bool:
        return self.format.endswith("-srgb")


def _srgb_flag(srgb: bool | None, kind: str | None) -> bool:
    if kind is not None:
        if kind not in TEXTURE_KINDS:
            raise UserError(f"unknown texture kind {kind!r}: choose 'color' (sRGB) or 'data' (linear)")
        if srgb is not None and srgb != TEXTURE_KINDS[kind]:
            raise UserError(f"texture kind {kind!r} contradicts srgb={srgb}: give one of them")
        return TEXTURE_KINDS[kind]
    if srgb is None:
        raise UserError(
            "say whether the texture is colour (srgb=True / kind='color') or data (srgb=False / kind='data')"
        )
    return bool(srgb)


def create_texture(
    ctx: GPUContext,
    source,
    *,
    srgb: bool | None = None,
    kind: str | None = None,
    mips: bool = True,
    label: str = "texture",
) -> Texture:
    """Load or take pixels, upload them, and fill the mip chain on the GPU.

    ``srgb`` (or ``kind``: 'color' / 'data') is required: colour textures use
    rgba8unorm-srgb so sampling returns linear values; data textures (normal maps,
    roughness) use rgba8unorm so the bytes are used as they are.
    """
    fmt = SRGB_FORMAT if _srgb_flag(srgb, kind) else LINEAR_FORMAT
    pixels = image_pixels(source, max_dim=ctx.limit(MAX_DIM_LIMIT))
    height, width = pixels.shape[:2]
    levels = mip_level_count(width, height) if mips else 1
    texture = ctx.device.create_texture(
        label=label,
        size=(width, height, 1),
        format=fmt,
        mip_level_count=levels,
        usage=wgpu.TextureUsage.TEXTURE_BINDING
        | wgpu.TextureUsage.COPY_DST
        | wgpu.TextureUsage.COPY_SRC
        | wgpu.TextureUsage.RENDER_ATTACHMENT,
    )
    upload_level(ctx, texture, pixels, 0)
    if levels > 1:
        generate_mipmaps(ctx, texture)
    view = texture.create_view()
    return Texture(texture=texture, view=view, size=(width, height), format=fmt, mip_level_count=levels)


def upload_level(ctx: GPUContext, texture: wgpu.GPUTexture, pixels: np.ndarray, level: int = 0) -> None:
    """Copy (H, W, 4) uint8 pixels into one mip level.

    This one call stands for the course's staging upload: create a host-visible
    staging buffer, map it and memcpy the pixels, transition the image
    UNDEFINED -> TRANSFER_DST_OPTIMAL with a barrier, vkCmdCopyBufferToImage, then
    transition TRANSFER_DST_OPTIMAL -> SHADER_READ_ONLY_OPTIMAL before the first
    sampling. wgpu stages the bytes in its own upload buffer, records the copy on
    the queue, and tracks the texture's usage so it inserts both transitions itself
    (the second one when a pass first binds the texture for sampling). Unlike
    copy_buffer_to_texture, write_texture needs no 256-byte row alignment.
    """
    height, width = pixels.shape[:2]
    ctx.queue.write_texture(
        {"texture": texture, "mip_level": level, "origin": (0, 0, 0)},
        np.ascontiguousarray(pixels, dtype=np.uint8),
        {"offset": 0, "bytes_per_row": width * 4, "rows_per_image": height},
        (width, height, 1),
    )


def _mipmap_pipeline(device: wgpu.GPUDevice, fmt: str) -> tuple[wgpu.GPURenderPipeline, wgpu.GPUBindGroupLayout]:
    """Made once per device and format (the device's "mipmap-pipelines" cache: wgpu_path/device/gpu_cache.py)."""
    return device_cache(device, "mipmap-pipelines", 16).get(fmt, lambda: _make_mipmap_pipeline(device, fmt))


def _make_mipmap_pipeline(device: wgpu.GPUDevice, fmt: str) -> tuple[wgpu.GPURenderPipeline, wgpu.GPUBindGroupLayout]:
    module = create_shader_module(device, "mipmap.wgsl")
    bgl = device.create_bind_group_layout(
        label="mipmap-src",
        entries=[
            {
                "binding": 0,
                "visibility": wgpu.ShaderStage.FRAGMENT,
                "texture": {"sample_type": "unfilterable-float", "view_dimension": "2d"},
            }
        ],
    )
    pipeline = device.create_render_pipeline(
        label=f"mipmap-{fmt}",
        layout=device.create_pipeline_layout(bind_group_layouts=[bgl]),
        vertex={"module": module, "entry_point": "vs_main", "buffers": []},
        primitive={"topology": "triangle-list", "cull_mode": "none"},
        depth_stencil=None,
        multisample={"count": 1, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
        fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": fmt}]},
    )
    return pipeline, bgl


def _level_view(texture: wgpu.GPUTexture, level: int) -> wgpu.GPUTextureView:
    return texture.create_view(base_mip_level=level, mip_level_count=1)


def generate_mipmaps(ctx: GPUContext, texture: wgpu.GPUTexture) -> None:
    """Fill levels 1.. of ``texture`` from level 0, gamma-correct, one render pass per level.

    The course does this with vkCmdBlitImage from level i-1 to level i, and between
    levels a barrier that moves level i-1 from TRANSFER_DST to TRANSFER_SRC (and at
    the end every level to SHADER_READ_ONLY). Here each level is a render pass that
    reads the previous level through a one-level view and draws a fullscreen
    triangle into a one-level view of the next; wgpu sees the previous pass wrote
    the level this one reads, and inserts the same barrier between the passes.

    mipmap.wgsl averages in linear light: reading an rgba8unorm-srgb view decodes
    to linear, and writing the -srgb render target encodes again. The filter is an
    exact area-weighted box: for even sides it is the 2x2 average; for odd sides
    (non-power-of-two textures, each level max(1, side >> 1)) a destination texel
    covers 2 + 1/n source texels and the edge ones get fractional weights, so no
    source texel is dropped (a linear vkCmdBlitImage would blur or skip them).
    Data textures (rgba8unorm) take the same path and average the stored values.
    """
    pipeline, bgl = _mipmap_pipeline(ctx.device, texture.format)
    encoder = ctx.device.create_command_encoder(label="mipmaps")
    for level in range(1, texture.mip_level_count):
        bind_group = ctx.device.create_bind_group(
            layout=bgl, entries=[{"binding": 0, "resource": _level_view(texture, level - 1)}]
        )
        render_pass = encoder.begin_render_pass(
            label=f"mip-{level}",
            color_attachments=[
                {
                    "view": _level_view(texture, level),
                    "clear_value": (0, 0, 0, 0),
                    "load_op": "clear",
                    "store_op": "store",
                }
            ],
        )
        render_pass.set_pipeline(pipeline)
        render_pass.set_bind_group(0, bind_group)
        render_pass.draw(3)
        render_pass.end()
    ctx.queue.submit([encoder.finish()])


def read_mip(ctx: GPUContext, texture: wgpu.GPUTexture, level: int) -> np.ndarray:
    """One mip level of an RGBA8 texture as (h, w, 4) uint8 stored bytes (tests, debugging)."""
    return read_texture(ctx, texture, level)


# ---------------------------------------------------------------------------
# Samplers (the description is the course core's: wgpurender/core/course/samplers.py)
# ---------------------------------------------------------------------------


def _cached_sampler(device: wgpu.GPUDevice, spec: SamplerSpec) -> wgpu.GPUSampler:
    """One sampler per device and spec (the device's "samplers" cache: wgpurender/wgpu_path/device/gpu_cache.py)."""
    return device_cache(device, "samplers").get(spec, lambda: _make_sampler(device, spec))


def _make_sampler(device: wgpu.GPUDevice, spec: SamplerSpec) -> wgpu.GPUSampler:
    return device.create_sampler(
        label="sampler",
        address_mode_u=spec.address_mode_u,
        address_mode_v=spec.address_mode_v,
        address_mode_w=spec.address_mode_w,
        mag_filter=spec.mag_filter,
        min_filter=spec.min_filter,
        mipmap_filter=spec.mipmap_filter,
        lod_min_clamp=spec.lod_min_clamp,
        lod_max_clamp=spec.lod_max_clamp,
        max_anisotropy=spec.max_anisotropy,
    )


def create_sampler(ctx: GPUContext, spec: SamplerSpec | dict | None = None) -> wgpu.GPUSampler:
    """The sampler for a spec (a SamplerSpec or a dict for SamplerSpec.from_dict), one per distinct spec."""
    if spec is None:
        spec = TRILINEAR
    elif isinstance(spec, dict):
        spec = SamplerSpec.from_dict(spec)
    return _cached_sampler(ctx.device, spec)
