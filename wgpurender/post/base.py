"""What every post-processing effect shares: parameters, a uniform buffer, a cached pipeline, one draw.

An effect is a full-screen triangle whose fragment shader reads the previous
result as a sampled texture and writes one colour target.

Why a texture and not an input attachment: the course reads the previous pass
through a Vulkan input attachment (a second subpass, ``subpassLoad``), which lets
a tiling GPU keep the pixel in on-chip tile memory. WebGPU has no subpasses (it
must map onto Metal and D3D12, which do not expose them), so every effect is its
own render pass and the image makes a full round trip through memory: written
by one pass, read back by the next. On desktop GPUs and on lavapipe subpasses
are not tile-local anyway, so there the cost is the same; the bandwidth saving
lost is a mobile one. The trade we do get: an effect may read *neighbouring*
pixels (FXAA, sharpen), which an input attachment forbids.

Colour encoding rule (see also :mod:`wgpurender.post.srgb`): float textures hold
linear values; 8-bit textures hold sRGB-encoded values. For ``-srgb`` formats
the hardware encodes on write and decodes on read, so shaders always see linear
values there. Only a plain 8-bit unorm target (``rgba8unorm``, ``bgra8unorm``:
some swapchains) needs the sRGB curve in a shader, and that is the ``srgb``
effect's job, always last in a chain.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import wgpu

from ..errors import UserError
from ..shaders import create_shader_module, load_wgsl
from .cache import BoundedCache

COMMON_WGSL = "post_common.wgsl"

# 8-bit formats the hardware does not encode: a shader must apply the sRGB curve.
SHADER_ENCODED_FORMATS = frozenset({"rgba8unorm", "bgra8unorm"})
HARDWARE_ENCODED_FORMATS = frozenset({"rgba8unorm-srgb", "bgra8unorm-srgb"})


def needs_shader_encoding(fmt: str) -> bool:
    """True when writing linear values to ``fmt`` needs the sRGB curve applied in a shader."""
    return fmt in SHADER_ENCODED_FORMATS


def encoding_of(fmt: str) -> str:
    """Who encodes values written to ``fmt``: 'hardware', 'shader' or 'none' (linear float)."""
    if fmt in HARDWARE_ENCODED_FORMATS:
        return "hardware"
    if fmt in SHADER_ENCODED_FORMATS:
        return "shader"
    return "none"


@dataclass(frozen=True)
class Param:
    """One effect parameter: a float in [lo, hi], or a choice among names (packed as its index)."""

    name: str
    default: float | str
    doc: str
    lo: float = float("-inf")
    hi: float = float("inf")
    choices: tuple[str, ...] = ()

    def validate(self, value: Any, effect: str) -> float | str:
        if self.choices:
            if not isinstance(value, str) or value not in self.choices:
                raise UserError(
                    f"post effect {effect!r}: {self.name} must be one of {', '.join(self.choices)}, got {value!r}"
                )
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise UserError(f"post effect {effect!r}: {self.name} must be a number, got {value!r}")
        if not (self.lo <= value <= self.hi):
            raise UserError(f"post effect {effect!r}: {self.name} must be in [{self.lo}, {self.hi}], got {value}")
        return float(value)

    def packed(self, value: float | str) -> float:
        return float(self.choices.index(value)) if self.choices else float(value)

    def describe(self) -> str:
        if self.choices:
            return f"{self.name} = {'|'.join(self.choices)} (default {self.default!r}): {self.doc}"
        return f"{self.name} = number in [{self.lo}, {self.hi}] (default {self.default}): {self.doc}"


@dataclass(frozen=True)
class EffectDescription:
    """What the render plan shows for one effect in a chain: pure data, no GPU objects."""

    name: str
    params: dict[str, float | str]
    input_format: str
    output_format: str
    shader: str
    summary: str
    notes: tuple[str, ...] = field(default=())

    def line(self) -> str:
        params = ", ".join(f"{k}={v}" for k, v in self.params.items())
        text = f"{self.name}({params}): {self.input_format} -> {self.output_format}"
        return text + "".join(f"; {n}" for n in self.notes)


@dataclass(frozen=True)
class DrawStep:
    """One full-screen draw of an effect's pass: a fragment entry point and, when the effect has a depth
    attachment (``PostEffect.depth_format``), how that draw tests and writes depth. Most effects have one
    step; FXAA has two, so that a depth test can skip whole blocks of pixels (post/fxaa.py says why)."""

    entry_point: str = "fs_main"
    depth_compare: str = "always"
    depth_write: bool = False


# (device, effect name, target format, step) -> pipeline; (device, effect name) -> layout; samplers per device.
_PIPELINES: dict[tuple, wgpu.GPURenderPipeline] = {}
_LAYOUTS: dict[tuple, wgpu.GPUPipelineLayout] = {}
_SAMPLERS: dict[wgpu.GPUDevice, wgpu.GPUSampler] = {}


def effect_source(shader: str) -> str:
    """The WGSL of an effect: post_common.wgsl followed by the effect's own file."""
    return load_wgsl(COMMON_WGSL) + "\n" + load_wgsl(shader)


def linear_clamp_sampler(device: wgpu.GPUDevice) -> wgpu.GPUSampler:
    if device not in _SAMPLERS:
        _SAMPLERS[device] = device.create_sampler(
            label="post-linear-clamp",
            mag_filter="linear",
            min_filter="linear",
            address_mode_u="clamp-to-edge",
            address_mode_v="clamp-to-edge",
        )
    return _SAMPLERS[device]


class PostEffect:
    """A full-screen effect. Subclasses set the class attributes; most need no code at all."""

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    shader: ClassVar[str] = ""  # file in shaders_wgsl/, used after post_common.wgsl
    params_spec: ClassVar[tuple[Param, ...]] = ()
    filtering: ClassVar[bool] = False  # samples with a linear sampler (needs a filterable input format)
    steps: ClassVar[tuple[DrawStep, ...]] = (DrawStep(),)  # the draws of the effect's pass, in order
    depth_format: ClassVar[str | None] = None  # a depth attachment for the pass (cleared to 1, not stored)

    def __init__(self, **params: Any) -> None:
        known = {p.name: p for p in self.params_spec}
        unknown = sorted(set(params) - set(known))
        if unknown:
            valid = ", ".join(known) or "none"
            raise UserError(f"post effect {self.name!r} has no parameter {unknown[0]!r}: valid parameters are {valid}")
        self.params: dict[str, float | str] = {
            p.name: p.validate(params.get(p.name, p.default), self.name) for p in self.params_spec
        }
        self._buffers: dict[wgpu.GPUDevice, wgpu.GPUBuffer] = {}
        # Per-frame objects, reused while their inputs are the same objects (see post/cache.py):
        self._uploaded: dict[wgpu.GPUDevice, tuple] = {}  # parameter values last written to the buffer
        self._groups: BoundedCache[wgpu.GPUBindGroup] = BoundedCache()  # (device, source, target format)
        self._target_views: BoundedCache[wgpu.GPUTextureView] = BoundedCache()  # target texture
        self._depth_views: BoundedCache[wgpu.GPUTextureView] = BoundedCache(2)  # (device, size)

    def clear_cache(self) -> None:
        """Drop cached bind groups and views (the chain calls it when its textures are replaced)."""
        self._groups.clear()
        self._target_views.clear()
        self._depth_views.clear()

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return f"{type(self).__name__}({args})"

    # -- description (for the render plan) ---------------------------------
    def notes(self, input_format: str, output_format: str) -> tuple[str, ...]:
        """Format-dependent remarks for the plan; subclasses add their own."""
        return ()

    def describe(self, input_format: str, output_format: str) -> EffectDescription:
        return EffectDescription(
            name=self.name,
            params=dict(self.params),
            input_format=input_format,
            output_format=output_format,
            shader=self.shader,
            summary=self.summary,
            notes=self.notes(input_format, output_format),
        )

    # -- GPU side -----------------------------------------------------------
    def pack_params(self) -> np.ndarray:
        """The uniform block: one f32 per parameter in declaration order, padded to 16 bytes."""
        values = [p.packed(self.params[p.name]) for p in self.params_spec]
        padded = np.zeros(max(4, -(-len(values) // 4) * 4), dtype=np.float32)
        padded[: len(values)] = values
        return padded

    def constants(self, target_format: str) -> dict[str, float]:
        """Pipeline-overridable WGSL constants for a target format (none by default)."""
        return {}

    def _layout_entries(self) -> list[dict]:
        frag = wgpu.ShaderStage.FRAGMENT
        sample_type = "float" if self.filtering else "unfilterable-float"
        entries = [{"binding": 0, "visibility": frag, "texture": {"sample_type": sample_type, "view_dimension": "2d"}}]
        if self.filtering:
            entries.append({"binding": 1, "visibility": frag, "sampler": {"type": "filtering"}})
        if self.params_spec:
            entries.append({"binding": 2, "visibility": frag, "buffer": {"type": "uniform"}})
        return entries

    def _pipeline_layout(self, device: wgpu.GPUDevice) -> wgpu.GPUPipelineLayout:
        """One layout per effect, shared by its steps' pipelines (so one bind group serves every step)."""
        key = (device, self.name)
        if key not in _LAYOUTS:
            bgl = device.create_bind_group_layout(label=f"post-{self.name}", entries=self._layout_entries())
            _LAYOUTS[key] = device.create_pipeline_layout(label=f"post-{self.name}", bind_group_layouts=[bgl])
        return _LAYOUTS[key]

    def pipeline(self, device: wgpu.GPUDevice, target_format: str, step: int = 0) -> wgpu.GPURenderPipeline:
        """The pipeline of one step of this effect writing ``target_format``, made once per (effect, format)."""
        key = (device, self.name, target_format, step)
        if key not in _PIPELINES:
            draw = self.steps[step]
            module = create_shader_module(device, self.shader, effect_source(self.shader))
            depth = None
            if self.depth_format is not None:
                depth = {"format": self.depth_format, "depth_write_enabled": draw.depth_write,
                         "depth_compare": draw.depth_compare}
            _PIPELINES[key] = device.create_render_pipeline(
                label=f"post-{self.name}-{target_format}-{draw.entry_point}",
                layout=self._pipeline_layout(device),
                vertex={"module": module, "entry_point": "vs_main", "buffers": []},
                primitive={"topology": "triangle-list", "cull_mode": "none"},
                depth_stencil=depth,
                multisample={"count": 1, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
                fragment={
                    "module": module,
                    "entry_point": draw.entry_point,
                    "targets": [{"format": target_format}],
                    "constants": self.constants(target_format),
                },
            )
        return _PIPELINES[key]

    def _depth_attachment(self, device: wgpu.GPUDevice, size: tuple[int, int]) -> dict | None:
        if self.depth_format is None:
            return None
        view = self._depth_views.get((device, size), lambda: device.create_texture(
            label=f"post-{self.name}-depth", size=(size[0], size[1], 1), format=self.depth_format,
            usage=wgpu.TextureUsage.RENDER_ATTACHMENT).create_view())
        return {"view": view, "depth_clear_value": 1.0, "depth_load_op": "clear", "depth_store_op": "discard"}

    def _uniform_buffer(self, device: wgpu.GPUDevice) -> wgpu.GPUBuffer:
        """The parameter buffer, rewritten only when a parameter changed since the last write."""
        if device not in self._buffers:
            self._buffers[device] = device.create_buffer(
                label=f"post-{self.name}-params",
                size=self.pack_params().nbytes,
                usage=wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST,
            )
        values = tuple(self.params.values())
        if self._uploaded.get(device) != values:
            device.queue.write_buffer(self._buffers[device], 0, self.pack_params().tobytes())
            self._uploaded[device] = values
        return self._buffers[device]

    def _bind_group(self, device: wgpu.GPUDevice, pipeline: wgpu.GPURenderPipeline,
                    source: wgpu.GPUTexture) -> wgpu.GPUBindGroup:
        entries = [{"binding": 0, "resource": source.create_view()}]
        if self.filtering:
            entries.append({"binding": 1, "resource": linear_clamp_sampler(device)})
        if self.params_spec:
            buffer = self._buffers[device]
            entries.append({"binding": 2, "resource": {"buffer": buffer, "offset": 0, "size": buffer.size}})
        return device.create_bind_group(label=f"post-{self.name}", layout=pipeline.get_bind_group_layout(0),
                                        entries=entries)

    def encode(
        self,
        device: wgpu.GPUDevice,
        encoder: wgpu.GPUCommandEncoder,
        source: wgpu.GPUTexture,
        target: wgpu.GPUTexture,
        timestamp_writes: dict | None = None,
    ) -> None:
        """Record one render pass: read ``source`` (single-sample), write all of ``target``.

        Parameters are uploaded at record time, so changing ``self.params``
        between frames takes effect on the next frame.
        """
        if source.sample_count != 1:
            raise UserError(f"post effect {self.name!r} reads a multisampled texture: resolve it first")
        if tuple(source.size[:2]) != tuple(target.size[:2]):
            raise UserError(f"post effect {self.name!r}: source {source.size[:2]} and target {target.size[:2]} differ")
        pipelines = [self.pipeline(device, target.format, i) for i in range(len(self.steps))]
        pipeline = pipelines[0]
        if self.params_spec:
            self._uniform_buffer(device)
        bind_group = self._groups.get((device, source, target.format),
                                      lambda: self._bind_group(device, pipeline, source))
        # load, not clear: the full-screen triangle writes every pixel (no discard, no blending), so a clear
        # is wasted work (WebGPU has no "don't care" load op; the raw subpass uses DONT_CARE). ~5% of a pass.
        render_pass = encoder.begin_render_pass(
            label=f"post-{self.name}",
            color_attachments=[{"view": self._target_views.get(target, target.create_view), "load_op": "load",
                                "store_op": "store"}],
            depth_stencil_attachment=self._depth_attachment(device, (target.size[0], target.size[1])),
            timestamp_writes=timestamp_writes,
        )
        render_pass.set_bind_group(0, bind_group)
        for step_pipeline in pipelines:
            render_pass.set_pipeline(step_pipeline)
            render_pass.draw(3)
        render_pass.end()
