"""Course step 1a: clear an image without a render pass (vkCmdClearColorImage)."""

from __future__ import annotations

import wgpu

from ..native import clear_texture
from .base import Stage


class ClearTransfer(Stage):
    name = "clear"
    summary = "clear the image with a transfer command, no render pass (to zero: WebGPU's clear has no colour)"
    course_step = "1a: clear without a render pass (vkCmdClearColorImage)"
    order = 1.0
    clear_color = (0.0, 0.0, 0.0, 0.0)

    def draw(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        clear_texture(self.ctx, encoder, target)
