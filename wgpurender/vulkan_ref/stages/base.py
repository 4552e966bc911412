"""What every raw-Vulkan stage has in common (the counterpart of wgpurender/stages/base.py).

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

from ..images import Image, create_image
from ..instance import VulkanContext

TARGET_USAGE = (
    vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | vk.VK_IMAGE_USAGE_TRANSFER_SRC_BIT | vk.VK_IMAGE_USAGE_TRANSFER_DST_BIT
)


class RefStage:
    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    order: ClassVar[float] = 0.0
    supports_msaa: ClassVar[bool] = False
    requires_msaa: ClassVar[bool] = False
    default_msaa: ClassVar[int] = 1
    default_format: ClassVar[str] = "rgba8unorm-srgb"

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
