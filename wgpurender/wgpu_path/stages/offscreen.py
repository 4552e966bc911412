"""Course step 3a: render into an image that is not the output, then copy it over.

The course renders into its own VkImage and copies it out (vkCmdCopyImage /
vkCmdCopyImageToBuffer). Here the triangle goes into a texture this stage owns,
and a texture-to-texture copy moves it to whatever the caller gave us (the
headless target, or the window's swapchain image). Headless callers then read
the target back with targets.read_texture.
"""

from __future__ import annotations

import wgpu

from wgpurender.core.course.triangle import BACKGROUND
from wgpurender.wgpu_path.stages.base import Stage


class Offscreen(Stage):
    name = "offscreen"
    summary = "render the triangle into an offscreen texture, then copy it to the output"

    def setup(self) -> None:
        self.pipeline = self.basic_pipeline("triangle.wgsl")
        self.image: wgpu.GPUTexture | None = None

    def on_resize(self, size: tuple[int, int]) -> None:
        self.image = self.device.create_texture(
            label="offscreen-image",
            size=(size[0], size[1], 1),
            format=self.format,
            usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC,
        )
        self.image_view = self.image.create_view()

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        render_pass = encoder.begin_render_pass(
            color_attachments=[
                {"view": self.image_view, "clear_value": BACKGROUND, "load_op": "clear", "store_op": "store"}
            ]
        )
        render_pass.set_pipeline(self.pipeline)
        render_pass.draw(3)
        render_pass.end()
        encoder.copy_texture_to_texture({"texture": self.image}, {"texture": target}, (self.size[0], self.size[1], 1))
