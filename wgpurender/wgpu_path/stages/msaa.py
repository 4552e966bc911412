"""Course step 3b: 4x MSAA into a multisampled image, resolved into a single-sample one.

The Vulkan version is a render pass with a 4-sample colour attachment and a
resolve attachment (pResolveAttachments). The parts enabling MSAA, all in this file:

1. the pipeline's multisample state: ``count = 4`` (every pipeline drawing into the
   multisampled image must say so);
2. a multisampled colour texture (``sample_count = 4``, RENDER_ATTACHMENT only), made
   per size;
3. the pass's colour attachment is that texture, ``resolve_target`` the single-sample
   output: the resolve (average of the samples) happens at the end of the pass, and
   ``store_op = "discard"`` says the samples themselves need not be kept.

Other stages with ``--msaa 4`` get the same three parts from base.py.
"""

from __future__ import annotations

import wgpu

from wgpurender.core.course.triangle import BACKGROUND
from wgpurender.wgpu_path.stages.base import Stage


class Msaa(Stage):
    name = "msaa"
    summary = "the triangle with 4x MSAA, resolved into a single-sample image"

    def setup(self) -> None:
        self.pipeline = self.basic_pipeline("triangle.wgsl")  # 1. multisample={"count": self.msaa, ...}
        self._msaa_view = None  # the multisampled view, made in resize()

    def resize(self, size: tuple[int, int]) -> None:
        """Replaces base.py's resize, which would make the same image for us."""
        if size == self.size:
            return
        self.size = size
        if self.msaa > 1:  # 2. the multisampled colour image
            self._msaa_view = self.device.create_texture(
                label="msaa-color",
                size=(size[0], size[1], 1),
                format=self.format,
                usage=wgpu.TextureUsage.RENDER_ATTACHMENT,
                sample_count=self.msaa,
            ).create_view()

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        output = self.target_view(target)
        if self.msaa == 1:
            attachment = {"view": output, "clear_value": BACKGROUND, "load_op": "clear", "store_op": "store"}
        else:  # 3. draw into the samples, resolve into the output, drop the samples
            attachment = {"view": self._msaa_view, "resolve_target": output, "clear_value": BACKGROUND,
                          "load_op": "clear", "store_op": "discard"}
        render_pass = encoder.begin_render_pass(color_attachments=[attachment])
        render_pass.set_pipeline(self.pipeline)
        render_pass.draw(3)
        render_pass.end()
