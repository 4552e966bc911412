"""Course step 1a: clear an image without a render pass (vkCmdClearColorImage)."""

from __future__ import annotations

import wgpu

from wgpurender.core.course.triangle import TRANSFER_CLEAR_COLOR
from wgpurender.wgpu_path.device.native import clear_texture
from wgpurender.wgpu_path.stages.base import Stage


class ClearTransfer(Stage):
    name = "clear"
    summary = "clear the image with a transfer command, no render pass (to zero: WebGPU's clear has no colour)"
    clear_color = TRANSFER_CLEAR_COLOR

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        clear_texture(self.ctx, encoder, target)
