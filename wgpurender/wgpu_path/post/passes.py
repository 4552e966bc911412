"""The two small runners of a planned post pass: a render pass (fragment) or a dispatch (compute).

Both run the shader that wgpu_path/post/shaders.py generates for the plan's :class:`~core.plan.PostPass`,
with the same bindings: 0 the input texture, 1 a linear clamp sampler (effects that filter), 2 the pass's
parameter struct (steps with parameters), and on the compute path 3 the storage texture written.

Pipelines and layouts are made once per device and shader text (wgpurender/wgpu_path/device/gpu_cache.py); bind groups
and views once per (source, target) texture pair, in a small cache that a swapchain cannot grow. A fragment
pass's draws are a render bundle recorded once per source texture: a frame replays it with one call.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable

import wgpu

from wgpurender.core.errors import UserError
from wgpurender.core.plan import PostPass
from wgpurender.wgpu_path.device.gpu_cache import GpuCache, device_cache
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.post.shaders import dispatch_groups, pack_pass, pass_source, shape_of, srgb_constant

FRAGMENT, COMPUTE = wgpu.ShaderStage.FRAGMENT, wgpu.ShaderStage.COMPUTE


def linear_clamp_sampler(device: wgpu.GPUDevice) -> wgpu.GPUSampler:
    return device_cache(device, "samplers").get("post-linear-clamp", lambda: device.create_sampler(
        label="post-linear-clamp", mag_filter="linear", min_filter="linear",
        address_mode_u="clamp-to-edge", address_mode_v="clamp-to-edge"))


class PlannedPass:
    """What both runners share: the generated shader, its layout, the parameter buffer and bind groups."""

    stage = FRAGMENT

    def __init__(self, device: wgpu.GPUDevice, p: PostPass, shape: tuple[int, int, int] | None = None,
                 tiled: str | None = None) -> None:
        self.device, self.p, self.shape = device, p, shape
        self.source = self.make_source(p, shape, tiled)
        self.key = hashlib.sha1(self.source.encode()).hexdigest()[:16]
        # a recomputing pass (post_intermediate = none) filters in its shader: no sampler
        self.filtering = p.steps[0].spec.filtering and not p.prelude
        self.buffer = None
        data = pack_pass(p)
        if data:
            self.buffer = device.create_buffer(label=f"post-{p.effect}-params", size=len(data),
                                               usage=wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST)
            device.queue.write_buffer(self.buffer, 0, data)
        self.layout = device_cache(device, "post-layouts").get((self.key, self.stage), self._make_layout)
        self.groups: GpuCache[wgpu.GPUBindGroup] = GpuCache(f"post-{p.effect}-bind-groups", 4)

    def make_source(self, p: PostPass, shape: tuple[int, int, int] | None, tiled: str | None) -> str:
        """The pass's WGSL (a runner that splits the pass over dispatches makes its own)."""
        return pass_source(p, shape, tiled)

    def module(self) -> wgpu.GPUShaderModule:
        return device_cache(self.device, "post-modules").get(self.key, lambda: create_shader_module(
            self.device, f"post_{self.p.effect}.wgsl (generated)", self.source))

    def _entries(self) -> list[dict]:
        sample_type = "float" if self.filtering else "unfilterable-float"
        entries = [{"binding": 0, "visibility": self.stage,
                    "texture": {"sample_type": sample_type, "view_dimension": "2d"}}]
        if self.filtering:
            entries.append({"binding": 1, "visibility": self.stage, "sampler": {"type": "filtering"}})
        if self.buffer is not None:
            entries.append({"binding": 2, "visibility": self.stage, "buffer": {"type": "uniform"}})
        return entries

    def _make_layout(self) -> wgpu.GPUPipelineLayout:
        bgl = self.device.create_bind_group_layout(label=f"post-{self.p.effect}", entries=self._entries())
        return self.device.create_pipeline_layout(label=f"post-{self.p.effect}", bind_group_layouts=[bgl])

    def _group_entries(self, source: wgpu.GPUTexture) -> list[dict]:
        entries = [{"binding": 0, "resource": source.create_view()}]
        if self.filtering:
            entries.append({"binding": 1, "resource": linear_clamp_sampler(self.device)})
        if self.buffer is not None:
            entries.append({"binding": 2, "resource": {"buffer": self.buffer, "offset": 0, "size": self.buffer.size}})
        return entries

    def check(self, source: wgpu.GPUTexture, target: wgpu.GPUTexture) -> None:
        if source.sample_count != 1:
            raise UserError(f"post pass {self.p.effect!r} reads a multisampled texture: resolve it first")
        if tuple(source.size[:2]) != tuple(target.size[:2]):
            raise UserError(f"post pass {self.p.effect!r}: source {source.size[:2]} and target "
                            f"{target.size[:2]} differ")


class FragmentPass(PlannedPass):
    """A render pass drawing the full-screen triangle once (twice with a mask: fs_mark, then fs_main)."""

    stage = FRAGMENT

    def __init__(self, device: wgpu.GPUDevice, p: PostPass) -> None:
        super().__init__(device, p)
        self.mask_format = p.steps[0].spec.mask_format if p.mask else None
        entries = ("fs_mark", "fs_main") if p.mask else ("fs_main",)
        self.pipelines = [self.pipeline(e) for e in entries]
        self.views: GpuCache[wgpu.GPUTextureView] = GpuCache(f"post-{p.effect}-views", 4)
        self.bundles: GpuCache[wgpu.GPURenderBundle] = GpuCache(f"post-{p.effect}-bundles", 4)

    def pipeline(self, entry_point: str) -> wgpu.GPURenderPipeline:
        depth = None
        if self.mask_format is not None:  # fs_mark writes the mask; fs_main runs where it is 1 (compare "less" 0)
            depth = {"format": self.mask_format, "depth_write_enabled": entry_point == "fs_mark",
                     "depth_compare": "always" if entry_point == "fs_mark" else "less"}
        fmt = self.p.output_format
        constants = {"SRGB_ENCODE": srgb_constant(self.p)} if any(s.effect == "srgb" for s in self.p.steps) else {}

        def make() -> wgpu.GPURenderPipeline:
            module = self.module()
            return self.device.create_render_pipeline(
                label=f"post-{self.p.effect}-{fmt}-{entry_point}", layout=self.layout,
                vertex={"module": module, "entry_point": "vs_main", "buffers": []},
                primitive={"topology": "triangle-list", "cull_mode": "none"},
                depth_stencil=depth,
                multisample={"count": 1, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
                fragment={"module": module, "entry_point": entry_point, "targets": [{"format": fmt}],
                          "constants": constants})

        return device_cache(self.device, "post-pipelines").get((self.key, "fragment", entry_point, fmt), make)

    def encode(self, encoder: wgpu.GPUCommandEncoder, source: wgpu.GPUTexture, target: wgpu.GPUTexture,
               mask: wgpu.GPUTexture | None = None, timestamp_writes: dict | None = None) -> None:
        self.check(source, target)
        depth = None
        if mask is not None:
            depth = {"view": self.views.get(mask, mask.create_view), "depth_clear_value": 1.0,
                     "depth_load_op": "clear", "depth_store_op": "discard"}
        # load, not clear: the full-screen triangle writes every pixel (no discard, no blending), so a clear
        # is wasted work (WebGPU has no "don't care" load op; the raw subpass uses DONT_CARE). ~5% of a pass.
        render_pass = encoder.begin_render_pass(
            label=f"post-{self.p.effect}",
            color_attachments=[{"view": self.views.get(target, target.create_view), "load_op": "load",
                                "store_op": "store"}],
            depth_stencil_attachment=depth, timestamp_writes=timestamp_writes)
        render_pass.execute_bundles([self.bundles.get((source,), lambda: self._bundle(source))])
        render_pass.end()

    def bound(self, source: wgpu.GPUTexture, target: wgpu.GPUTexture,
              mask: wgpu.GPUTexture | None = None) -> Callable[[wgpu.GPUCommandEncoder], None]:
        """:meth:`encode` between these textures with its checks, views, dicts and bundle made now, not per frame:
        the frame calls the result with its encoder (issue 31.4: the same calls, less Python per frame)."""
        self.check(source, target)
        return self.bound_source(source, mask)(target, self.views.get(target, target.create_view))

    def bound_source(self, source: wgpu.GPUTexture, mask: wgpu.GPUTexture | None = None) -> Callable:
        """:meth:`bound` with all but the target made now: ``bound_source(source, mask)(target, view)`` is the
        encode, for a target that changes every frame (a swapchain's image: PostRunner.bind) and its view."""
        label = f"post-{self.p.effect}"
        depth = None
        if mask is not None:
            depth = {"view": self.views.get(mask, mask.create_view), "depth_clear_value": 1.0,
                     "depth_load_op": "clear", "depth_store_op": "discard"}
        bundles = [self.bundles.get((source,), lambda: self._bundle(source))]

        def into(target: wgpu.GPUTexture, view: wgpu.GPUTextureView) -> Callable[[wgpu.GPUCommandEncoder], None]:
            colors = [{"view": view, "load_op": "load", "store_op": "store"}]

            def encode(encoder: wgpu.GPUCommandEncoder) -> None:
                render_pass = encoder.begin_render_pass(label=label, color_attachments=colors,
                                                        depth_stencil_attachment=depth)
                render_pass.execute_bundles(bundles)
                render_pass.end()

            return encode

        return into

    def _bundle(self, source: wgpu.GPUTexture) -> wgpu.GPURenderBundle:
        """The pass's draws (bind group, pipeline(s), full-screen triangle), recorded once per source texture.

        Nothing in them depends on the target (a bundle needs only its format), so one bundle serves every
        swapchain image; the frame replays it with one call instead of 3-5 (issue 22.2).
        """
        group = self.groups.get((source,), lambda: self.device.create_bind_group(
            label=f"post-{self.p.effect}", layout=self.pipelines[0].get_bind_group_layout(0),
            entries=self._group_entries(source)))
        bundle = self.device.create_render_bundle_encoder(
            label=f"post-{self.p.effect}", color_formats=[self.p.output_format],
            depth_stencil_format=self.mask_format)
        bundle.set_bind_group(0, group)
        for pipeline in self.pipelines:
            bundle.set_pipeline(pipeline)
            bundle.draw(3)
        return bundle.finish(label=f"post-{self.p.effect}")


class ComputePass(PlannedPass):
    """A dispatch writing a storage texture (then a copy, for an -srgb output); ``shape``: the plan's dispatch shape
    (``PostPass.shape``) unless a benchmark sweeps it."""

    stage = COMPUTE

    def _entries(self) -> list[dict]:
        return super()._entries() + [{"binding": 3, "visibility": COMPUTE, "storage_texture": {
            "access": "write-only", "format": self.p.output_format, "view_dimension": "2d"}}]

    def __init__(self, device: wgpu.GPUDevice, p: PostPass, shape: tuple[int, int, int] | None = None,
                 tiled: str | None = None) -> None:
        super().__init__(device, p, shape, tiled)
        constants = {"SRGB_ENCODE": srgb_constant(p)} if any(s.effect == "srgb" for s in p.steps) else {}
        self.pipeline = device_cache(device, "post-pipelines").get(
            (self.key, "compute", "cs_main", p.output_format), lambda: device.create_compute_pipeline(
                label=f"post-{p.effect}-{p.output_format}-compute", layout=self.layout,
                compute={"module": self.module(), "entry_point": "cs_main", "constants": constants}))

    def encode(self, encoder: wgpu.GPUCommandEncoder, source: wgpu.GPUTexture, target: wgpu.GPUTexture,
               copy_to: wgpu.GPUTexture | None = None, timestamp_writes: dict | None = None) -> None:
        compute_pass = encoder.begin_compute_pass(label=f"post-{self.p.effect}", timestamp_writes=timestamp_writes)
        self.dispatch(compute_pass, source, target)
        compute_pass.end()
        if copy_to is not None:
            self.copy(encoder, target, copy_to)

    def dispatch(self, compute_pass: wgpu.GPUComputePassEncoder, source: wgpu.GPUTexture,
                 target: wgpu.GPUTexture) -> None:
        """The pass's dispatch into an open compute pass (several planned passes may share one: PostRunner)."""
        self.check(source, target)
        group = self._group(source, target)
        compute_pass.set_pipeline(self.pipeline)
        compute_pass.set_bind_group(0, group)
        groups = dispatch_groups((target.size[0], target.size[1]), shape_of(self.p, self.shape))
        compute_pass.dispatch_workgroups(*groups, 1)

    def bound(self, source: wgpu.GPUTexture,
              target: wgpu.GPUTexture) -> Callable[[wgpu.GPUComputePassEncoder], None]:
        """:meth:`dispatch` between these textures with its check, bind group and workgroup count made now: the
        frame calls the result with its open compute pass (issue 31.4)."""
        self.check(source, target)
        group = self._group(source, target)
        pipeline = self.pipeline
        x, y = dispatch_groups((target.size[0], target.size[1]), shape_of(self.p, self.shape))

        def dispatch(compute_pass: wgpu.GPUComputePassEncoder) -> None:
            compute_pass.set_pipeline(pipeline)
            compute_pass.set_bind_group(0, group)
            compute_pass.dispatch_workgroups(x, y, 1)

        return dispatch

    def _group(self, source: wgpu.GPUTexture, target: wgpu.GPUTexture) -> wgpu.GPUBindGroup:
        return self.groups.get((source, target), lambda: self.device.create_bind_group(
            label=f"post-{self.p.effect}", layout=self.pipeline.get_bind_group_layout(0),
            entries=self._group_entries(source) + [{"binding": 3, "resource": target.create_view()}]))

    @staticmethod
    def copy(encoder: wgpu.GPUCommandEncoder, target: wgpu.GPUTexture, copy_to: wgpu.GPUTexture) -> None:
        encoder.copy_texture_to_texture({"texture": target}, {"texture": copy_to}, (target.size[0], target.size[1], 1))


def planned_pass(device: wgpu.GPUDevice, p: PostPass) -> FragmentPass | ComputePass:
    return ComputePass(device, p) if p.path == "compute" else FragmentPass(device, p)


__all__ = ["ComputePass", "FragmentPass", "PlannedPass", "linear_clamp_sampler", "planned_pass"]
