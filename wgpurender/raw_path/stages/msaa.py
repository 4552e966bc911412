"""Course step 3b: 4x MSAA: a 4-sample colour attachment resolved into the output (pResolveAttachments).

The parts enabling MSAA, all visible here:
1. the pipeline's rasterizationSamples = 4 (PipelineDesc.samples);
2. a multisampled colour image: TRANSIENT_ATTACHMENT usage, lazily allocated, never stored;
3. a render pass whose subpass writes that image and names the target as its resolve
   attachment (loadOp CLEAR, storeOp DONT_CARE for the samples); the resolve (average of
   the 4 samples) is written at the end of the subpass (renderpass.single_pass).
"""

from __future__ import annotations

import vulkan as vk

from wgpurender.core.course.triangle import BACKGROUND
from wgpurender.raw_path.device.images import Image
from wgpurender.raw_path.device.pipeline import set_viewport_and_scissor
from wgpurender.raw_path.device.renderpass import begin, create_framebuffer, single_pass
from wgpurender.raw_path.stages.base import RefStage


class Msaa(RefStage):
    name = "msaa"
    summary = "the triangle with 4x MSAA, resolved into a single-sample image"

    def setup(self) -> None:
        # 3. colour attachment (self.msaa samples) + resolve attachment (the target) in one subpass
        self.render_pass = single_pass(self.ctx, self.owned, self.format, self.msaa, BACKGROUND)
        # 2. the multisampled image (none at msaa 1: the pass then draws straight into the target)
        self.msaa_image = self.transient_msaa_image() if self.msaa > 1 else None
        self.pipeline = self.basic_pipeline("triangle.vert")  # 1. samples=self.msaa

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        views = [target] if self.msaa_image is None else [self.msaa_image, target]
        framebuffer = create_framebuffer(self.ctx, self.owned, self.render_pass, views)
        begin(cmd, self.render_pass, framebuffer, self.size)
        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.pipeline)
        set_viewport_and_scissor(cmd, self.size)
        vk.vkCmdDraw(cmd, 3, 1, 0, 0)
        vk.vkCmdEndRenderPass(cmd)
