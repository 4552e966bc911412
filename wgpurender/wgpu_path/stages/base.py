"""What every course stage has in common: a pipeline set up once, recorded into any colour texture.

A stage never owns its output texture: headless rendering passes an offscreen
texture, the window passes the swapchain image of the frame. Size-dependent
attachments (the multisampled colour image, the depth image) are made in
:meth:`Stage.resize`. The MSAA parts are spelled out in the msaa stage (msaa.py);
here they are shared by every stage that takes ``--msaa 4``.
"""

from __future__ import annotations

from typing import ClassVar

import wgpu

from wgpurender.core.course.formats import DEFAULT_FORMAT, SAMPLE_COUNTS
from wgpurender.core.course.steps import course_step, msaa_steps, step_msaa
from wgpurender.core.errors import UserError

# ctx.use_immediates' rule, imported with the stages: while a device started early (context.start_context) is
# still being made, not after it (issue 31.5)
from wgpurender.core.plan import post as _rules  # noqa: F401, I001
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module


def check_sample_count(ctx: GPUContext, msaa: int) -> int:
    if msaa not in SAMPLE_COUNTS:
        counts = ", ".join(map(str, SAMPLE_COUNTS))
        raise UserError(
            f"MSAA {msaa}x is not supported by {ctx.adapter.info['device']}: supported sample counts are {counts}"
        )
    return msaa


class Stage:
    """One step of the course. Subclasses set the class attributes and implement record()."""

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    supports_msaa: ClassVar[bool] = False
    default_msaa: ClassVar[int] = 1
    default_format: ClassVar[str] = DEFAULT_FORMAT

    def __init_subclass__(cls, **kwargs) -> None:
        """MSAA is the course step's fact (course/steps.py), the same for both paths' stages."""
        super().__init_subclass__(**kwargs)
        cls.supports_msaa, cls.default_msaa = step_msaa(cls.name)

    @classmethod
    def course_step(cls) -> str:
        """'number: title' of the course step this stage stands for (wgpurender/core/course/steps.py)."""
        step = course_step(cls.name)
        return f"{step.number}: {step.title}" if step else "(not in the course table yet)"

    def __init__(self, ctx: GPUContext, color_format: str, msaa: int | None = None) -> None:
        self.ctx = ctx
        self.device = ctx.device
        self.format = color_format
        self.msaa = check_sample_count(ctx, self.default_msaa if msaa is None else msaa)
        if self.msaa > 1 and not self.supports_msaa:
            raise UserError(f"stage {self.name!r} does not use MSAA: leave out --msaa (stages with MSAA: "
                            f"{', '.join(msaa_steps())})")
        self.size = (0, 0)
        self._msaa_view: wgpu.GPUTextureView | None = None
        self._target_view: tuple[wgpu.GPUTexture, wgpu.GPUTextureView] | None = None  # (texture, its view)
        self.setup()

    # -- for subclasses -------------------------------------------------
    def setup(self) -> None:
        """Create pipelines, buffers and bind groups that do not depend on the size."""

    def on_resize(self, size: tuple[int, int]) -> None:
        """Create size-dependent attachments beyond the MSAA colour image."""

    def record(self, encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, t: float = 0.0) -> None:
        """Record this frame's commands into ``encoder``, drawing into ``target`` at time ``t``."""
        raise NotImplementedError

    # -- shared ----------------------------------------------------------
    def resize(self, size: tuple[int, int]) -> None:
        if size == self.size:
            return
        self.size = size
        if self.msaa > 1:
            self._msaa_view = self.multisampled_texture(size).create_view()
        self.on_resize(size)

    def multisampled_texture(self, size: tuple[int, int]) -> wgpu.GPUTexture:
        """The multisampled colour image: only ever rendered to and resolved, never read or copied."""
        return self.device.create_texture(
            label=f"{self.name}-msaa-color",
            size=(size[0], size[1], 1),
            format=self.format,
            usage=wgpu.TextureUsage.RENDER_ATTACHMENT,
            sample_count=self.msaa,
        )

    def color_attachment(self, target: wgpu.GPUTexture, clear=(0.0, 0.0, 0.0, 1.0)) -> dict:
        """The colour attachment for a pass: the target itself, or the MSAA image resolved into it.

        With MSAA the multisampled image is only a scratch attachment: store_op
        discard tells the driver it need not keep the samples after the resolve.
        """
        view = self.target_view(target)
        if self.msaa == 1:
            return {"view": view, "clear_value": clear, "load_op": "clear", "store_op": "store"}
        return {
            "view": self._msaa_view,
            "resolve_target": view,
            "clear_value": clear,
            "load_op": "clear",
            "store_op": "discard",
        }

    def target_view(self, target: wgpu.GPUTexture) -> wgpu.GPUTextureView:
        """A view of ``target``, made once per texture object (a frame loop draws into the same one)."""
        cached = self._target_view
        if cached is None or cached[0] is not target:
            cached = self._target_view = (target, target.create_view())
        return cached[1]

    def multisample_state(self) -> dict:
        return {"count": self.msaa, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False}

    def basic_pipeline(self, shader: str, vertex_buffers: list | None = None) -> wgpu.GPURenderPipeline:
        """The fixed-function state of the first triangle: no culling, no depth, one colour target."""
        module = create_shader_module(self.device, shader)
        layout = self.device.create_pipeline_layout(bind_group_layouts=[])
        return self.device.create_render_pipeline(
            label=shader,
            layout=layout,
            vertex={"module": module, "entry_point": "vs_main", "buffers": vertex_buffers or []},
            primitive={"topology": "triangle-list", "front_face": "ccw", "cull_mode": "none"},
            depth_stencil=None,
            multisample=self.multisample_state(),
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": self.format}]},
        )
