"""Course step 3c: 4x MSAA triangle, then a post effect reading the resolved image (the raw stage's twin).

The raw stage (wgpurender/raw_path/stages/msaa_post.py) is one render pass with two subpasses:
subpass 0 draws the triangle 4x multisampled and resolves it; subpass 1 reads the resolve as an
input attachment (subpassLoad) and writes it greyed into the output.

**Why wgpu needs a second render pass here.** WebGPU has no subpasses and no input attachments:
it is designed to map onto Metal and D3D12, which expose neither (gfx-rs/wgpu#10148 is open). So
this stage is two render passes recorded into one encoder:

- pass 1 (``record``): the MSAA colour attachment resolved into ``self.scene``, a texture with
  RENDER_ATTACHMENT | TEXTURE_BINDING usage (the raw path's resolve attachment needs only
  COLOR_ATTACHMENT | INPUT_ATTACHMENT and is never stored);
- pass 2 (``_post``): a full-screen triangle whose fragment shader reads ``self.scene`` with
  textureLoad through a bind group (set 0, binding 0), where the raw path binds an INPUT_ATTACHMENT
  descriptor. wgpu orders the two passes itself (the resolve's write before pass 2's read, the
  texture's usage transition): the raw path's subpass dependency 0 -> 1 has no API here.

What it costs: the resolved image is stored to memory by pass 1 and read back by pass 2, where a
tiling GPU keeps it in tile memory between subpasses; docs/benchmarks.md measures it. What it gains:
pass 2 could read any pixel (FXAA, sharpen), which an input attachment forbids.

The grey amount is a push constant on the raw path; here a uniform buffer, since immediates are
an optional wgpu feature (the 3d stage shows them with a uniform fallback).
"""

from __future__ import annotations

import numpy as np
import wgpu

from wgpurender.core.course.triangle import BACKGROUND
from wgpurender.core.errors import UserError
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.stages.base import Stage

GREY_AMOUNT = 1.0  # fully grey: the simplest effect to check against numpy (the raw stage's value)
SCENE_USAGE = wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.TEXTURE_BINDING


class MsaaPost(Stage):
    name = "msaa-post"
    summary = "4x MSAA triangle, then a grey post effect in a second render pass reading the resolved image"

    def setup(self) -> None:
        if self.msaa == 1:
            raise UserError("stage 'msaa-post' resolves a multisampled image in its first pass: use --msaa 4")
        self.draw_pipeline = self.basic_pipeline("triangle.wgsl")
        self._setup_post()

    def _setup_post(self) -> None:
        dev = self.device
        module = create_shader_module(dev, "msaa_post.wgsl")
        self.post_pipeline = dev.create_render_pipeline(
            label="msaa-post-post", layout="auto",
            vertex={"module": module, "entry_point": "vs_main", "buffers": []},
            primitive={"topology": "triangle-list", "cull_mode": "none"},
            depth_stencil=None, multisample={"count": 1, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": self.format}]},
        )
        self.post_buffer = dev.create_buffer_with_data(
            label="msaa-post-amount", data=np.array([GREY_AMOUNT, 0, 0, 0], dtype=np.float32),
            usage=wgpu.BufferUsage.UNIFORM,
        )
        self.post_group = None

    def on_resize(self, size: tuple[int, int]) -> None:
        """The resolve target: an image of its own, since the post pass must read it as a texture."""
        self.scene = self.device.create_texture(label="msaa-post-scene", size=(size[0], size[1], 1),
                                                format=self.format, usage=SCENE_USAGE)
        self.post_group = self.device.create_bind_group(
            layout=self.post_pipeline.get_bind_group_layout(0),
            entries=[{"binding": 0, "resource": self.scene.create_view()},
                     {"binding": 1, "resource": {"buffer": self.post_buffer}}],
        )

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(self.scene, BACKGROUND)])
        render_pass.set_pipeline(self.draw_pipeline)
        render_pass.draw(3)
        render_pass.end()
        self._post(encoder, target)

    def _post(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture) -> None:
        """Pass 2, the raw stage's subpass 1: every pixel is written, so the target is loaded, not cleared
        (the raw path's loadOp DONT_CARE has no WebGPU equivalent; load is the cheaper of the two)."""
        render_pass = encoder.begin_render_pass(color_attachments=[{
            "view": target.create_view(), "load_op": "load", "store_op": "store"}])
        render_pass.set_pipeline(self.post_pipeline)
        render_pass.set_bind_group(0, self.post_group)
        render_pass.draw(3)
        render_pass.end()
