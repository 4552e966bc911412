"""One render pass, two subpasses: 4x MSAA triangle, then a post effect through an input attachment.

The mechanism the final scene's post-processing needs, built on the triangle:
- subpass 0 draws the triangle into a 4-sample attachment, resolved into a
  single-sample one at the end of the subpass;
- subpass 1 draws a full-screen triangle whose fragment shader reads the
  resolved image with subpassLoad (descriptor type INPUT_ATTACHMENT, a set
  written with vkUpdateDescriptorSets) and writes it greyed into the output.
  The grey amount is a push constant (vkCmdPushConstants, fragment stage).
The subpass dependency 0 -> 1 (COLOR_ATTACHMENT_OUTPUT / COLOR_ATTACHMENT_WRITE
-> FRAGMENT_SHADER / INPUT_ATTACHMENT_READ, BY_REGION) is what makes the
resolve visible to subpass 1 (renderpass.msaa_post_pass).
"""

from __future__ import annotations

import struct

import vulkan as vk

from wgpurender.core.course.triangle import BACKGROUND, GREY_AMOUNT
from wgpurender.core.errors import UserError
from wgpurender.raw_path.device import descriptors
from wgpurender.raw_path.device.images import Image, create_image
from wgpurender.raw_path.device.pipeline import (
    PipelineDesc,
    create_pipeline,
    create_pipeline_layout,
    set_viewport_and_scissor,
)
from wgpurender.raw_path.device.renderpass import begin, create_framebuffer, msaa_post_pass
from wgpurender.raw_path.stages.base import RefStage


class MsaaPost(RefStage):
    name = "msaa-post"
    summary = "4x MSAA triangle, then a grey post effect in a second subpass reading it as an input attachment"
    requires_msaa = True

    def setup(self) -> None:
        if self.msaa == 1:
            raise UserError("stage 'msaa-post' resolves a multisampled image in its first subpass: use --msaa 4")
        ctx, owned = self.ctx, self.owned
        self.render_pass = msaa_post_pass(ctx, owned, self.format, self.format, self.msaa, BACKGROUND)
        self.scene = self.transient_msaa_image()
        usage = vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | vk.VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT
        self.resolved = create_image(ctx, owned, self.size, self.format, usage)
        self.draw_pipeline = create_pipeline(
            ctx, owned, PipelineDesc("triangle.vert", "color.frag", samples=self.msaa),
            create_pipeline_layout(ctx, owned), self.render_pass,
        )
        self._setup_post()

    def _setup_post(self) -> None:
        ctx, owned = self.ctx, self.owned
        bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT, vk.VK_SHADER_STAGE_FRAGMENT_BIT)]
        set_layout = descriptors.create_set_layout(ctx, owned, bindings)
        pool = descriptors.create_pool(ctx, owned, [bindings])
        (self.post_set,) = descriptors.allocate_sets(ctx, pool, [set_layout])
        descriptors.update(ctx, [descriptors.write_image(
            self.post_set, 0, self.resolved.view, vk.VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
            vk.VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT,
        )])
        push = vk.VkPushConstantRange(stageFlags=vk.VK_SHADER_STAGE_FRAGMENT_BIT, offset=0, size=4)
        self.post_layout = create_pipeline_layout(ctx, owned, [set_layout], [push])
        self.post_pipeline = create_pipeline(
            ctx, owned, PipelineDesc("fullscreen.vert", "post_grayscale.frag", subpass=1), self.post_layout,
            self.render_pass,
        )

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        framebuffer = create_framebuffer(self.ctx, self.owned, self.render_pass, [self.scene, self.resolved, target])
        begin(cmd, self.render_pass, framebuffer, self.size)
        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.draw_pipeline)
        set_viewport_and_scissor(cmd, self.size)
        vk.vkCmdDraw(cmd, 3, 1, 0, 0)
        vk.vkCmdNextSubpass(cmd, vk.VK_SUBPASS_CONTENTS_INLINE)
        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.post_pipeline)
        set_viewport_and_scissor(cmd, self.size)
        vk.vkCmdBindDescriptorSets(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.post_layout, 0, 1, [self.post_set],
                                   0, None)
        amount = vk.ffi.from_buffer(struct.pack("<f", GREY_AMOUNT))
        vk.vkCmdPushConstants(cmd, self.post_layout, vk.VK_SHADER_STAGE_FRAGMENT_BIT, 0, 4, amount)
        vk.vkCmdDraw(cmd, 3, 1, 0, 0)
        vk.vkCmdEndRenderPass(cmd)
