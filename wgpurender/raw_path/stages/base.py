"""What every raw-Vulkan stage has in common (the counterpart of wgpurender/wgpu_path/stages/base.py).

A stage is made for one size, format and sample count, creates what it needs in
:meth:`RefStage.setup` (every object registered with ``owned``, an ExitStack
that destroys them in reverse order), and records its commands into a command
buffer with :meth:`RefStage.record`. It renders into a target image it does not
own and must leave that image in TRANSFER_SRC_OPTIMAL, ready for the readback.
"""

from __future__ import annotations

from contextlib import ExitStack
from typing import ClassVar

import vulkan as vk

from wgpurender.core.course.formats import DEFAULT_FORMAT
from wgpurender.core.course.steps import step_msaa
from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.images import Image, create_image
from wgpurender.raw_path.device.pipeline import PipelineDesc, create_pipeline, create_pipeline_layout
from wgpurender.raw_path.device.renderpass import begin, create_framebuffer, single_pass

TARGET_USAGE = (
    vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | vk.VK_IMAGE_USAGE_TRANSFER_SRC_BIT | vk.VK_IMAGE_USAGE_TRANSFER_DST_BIT
)
# The layout a stage's target arrives in, cleared to zeros (raw_path/render.zero), as wgpu's textures start. A
# stage that writes it with transfer commands names this as its first barrier's old layout: a barrier from
# UNDEFINED lets the driver discard the contents (the Vulkan spec), so the zeros would hold only by luck.
TARGET_LAYOUT = vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL


class RefStage:
    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    supports_msaa: ClassVar[bool] = False
    requires_msaa: ClassVar[bool] = False
    default_msaa: ClassVar[int] = 1
    default_format: ClassVar[str] = DEFAULT_FORMAT

    def __init_subclass__(cls, **kwargs) -> None:
        """MSAA is the course step's fact (course/steps.py), the same for both paths' stages."""
        super().__init_subclass__(**kwargs)
        cls.supports_msaa, cls.default_msaa = step_msaa(cls.name)

    def __init__(self, ctx: VulkanContext, owned: ExitStack, fmt: str, msaa: int, size: tuple[int, int]) -> None:
        self.ctx = ctx
        self.owned = owned
        self.format = fmt
        self.msaa = msaa
        self.size = size
        self.setup()

    def setup(self) -> None:
        """Create render passes, pipelines, buffers: everything that does not depend on the target."""

    def record(self, cmd, target: Image, t: float = 0.0) -> None:
        raise NotImplementedError

    def transient_msaa_image(self, fmt: str | None = None) -> Image:
        """The multisampled colour attachment: only ever rendered to and resolved, never stored."""
        usage = vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | vk.VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT
        return create_image(self.ctx, self.owned, self.size, fmt or self.format, usage, self.msaa, lazy=True)

    def single_pass(self, clear_color, depth: bool = False) -> None:
        """One render pass with one subpass into the target (through a transient MSAA image at msaa > 1)."""
        self.render_pass = single_pass(self.ctx, self.owned, self.format, self.msaa, clear_color, depth=depth)
        self.msaa_image = self.transient_msaa_image() if self.msaa > 1 else None

    def begin_pass(self, cmd, target: Image, *extra: Image) -> None:
        """A framebuffer of [MSAA image,] target[, extra attachments] and vkCmdBeginRenderPass on it."""
        views = [target] if self.msaa_image is None else [self.msaa_image, target]
        framebuffer = create_framebuffer(self.ctx, self.owned, self.render_pass, [*views, *extra])
        begin(cmd, self.render_pass, framebuffer, self.size)

    def basic_pipeline(self, vert: str, frag: str = "color.frag", bindings=(), attributes=()):
        """The first triangle's pipeline: no culling, no depth, an empty layout (the course's fixed function)."""
        self.layout = create_pipeline_layout(self.ctx, self.owned)
        desc = PipelineDesc(vert=vert, frag=frag, samples=self.msaa, vertex_bindings=list(bindings),
                            vertex_attributes=list(attributes))
        return create_pipeline(self.ctx, self.owned, desc, self.layout, self.render_pass)
