"""What every course stage has in common: a pipeline set up once, drawn into any colour texture.

A stage never owns its output texture: headless rendering passes an offscreen
texture, the window passes the swapchain image of the frame. Size-dependent
attachments (the multisampled colour image, the depth image) are made in
:meth:`Stage.resize`.
"""

from __future__ import annotations

from typing import ClassVar

import wgpu

from ..errors import UserError
from ..gpu import GPUContext

SUPPORTED_SAMPLE_COUNTS = (1, 4)  # what WebGPU guarantees, and all that lavapipe offers


def check_sample_count(ctx: GPUContext, msaa: int) -> int:
    if msaa not in SUPPORTED_SAMPLE_COUNTS:
        counts = ", ".join(map(str, SUPPORTED_SAMPLE_COUNTS))
        raise UserError(
            f"MSAA {msaa}x is not supported by {ctx.adapter.info['device']}: supported sample counts are {counts}"
        )
    return msaa


class Stage:
    """One step of the course. Subclasses set the class attributes and implement draw()."""

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    course_step: ClassVar[str] = ""
    order: ClassVar[float] = 0.0
    supports_msaa: ClassVar[bool] = False
    default_msaa: ClassVar[int] = 1
    default_format: ClassVar[str] = "rgba8unorm-srgb"

    def __init__(self, ctx: GPUContext, color_format: str, msaa: int | None = None) -> None:
        self.ctx = ctx
        self.device = ctx.device
        self.format = color_format
        self.msaa = check_sample_count(ctx, self.default_msaa if msaa is None else msaa)
        if self.msaa > 1 and not self.supports_msaa:
            from . import all_stages

            with_msaa = ", ".join(name for name, cls in all_stages().items() if cls.supports_msaa)
            raise UserError(f"stage {self.name!r} does not use MSAA: leave out --msaa (stages with MSAA: {with_msaa})")
        self.size = (0, 0)
        self._msaa_view: wgpu.GPUTextureView | None = None
        self.setup()

    # -- for subclasses -------------------------------------------------
    def setup(self) -> None:
        """Create pipelines, buffers and bind groups that do not depend on the size."""

    def on_resize(self, size: tuple[int, int]) -> None:
        """Create size-dependent attachments beyond the MSAA colour image."""

    def draw(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        raise NotImplementedError

    # -- shared ----------------------------------------------------------
    def resize(self, size: tuple[int, int]) -> None:
        if size == self.size:
            return
        self.size = size
        if self.msaa > 1:
            tex = self.device.create_texture(
                label=f"{self.name}-msaa-color",
                size=(size[0], size[1], 1),
                format=self.format,
                usage=wgpu.TextureUsage.RENDER_ATTACHMENT,
                sample_count=self.msaa,
            )
            self._msaa_view = tex.create_view()
        self.on_resize(size)

    def color_attachment(self, target: wgpu.GPUTexture, clear=(0.0, 0.0, 0.0, 1.0)) -> dict:
        """The colour attachment for a pass: the target itself, or the MSAA image resolved into it.

        With MSAA the multisampled image is only a scratch attachment: store_op
        discard tells the driver it need not keep the samples after the resolve.
        """
        view = target.create_view()
        if self.msaa == 1:
            return {"view": view, "clear_value": clear, "load_op": "clear", "store_op": "store"}
        return {
            "view": self._msaa_view,
            "resolve_target": view,
            "clear_value": clear,
            "load_op": "clear",
            "store_op": "discard",
        }

    def multisample_state(self) -> dict:
        return {"count": self.msaa, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False}
