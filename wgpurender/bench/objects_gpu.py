"""Many objects animated, culled and drawn by the GPU: the CPU writes one 32-byte uniform per frame.

The same quads as bench/objects.py (same places, drift and colours), but what the CPU-animated modes
recompute in numpy and upload every frame (32 bytes an object: 32 MB a frame at a million) stays on the
GPU: each object's centre, phase and colour are uploaded once (16 bytes an object, in two buffers so
that 10M objects fit the default 128 MiB storage-binding limit). Per frame:

1. ``queue.write_buffer(params)``: the view (offset, zoom), the time, the count - 32 bytes;
2. ``clear_buffer`` of the indirect draw's instance count;
3. a compute pass (``cs_cull``, shaders_wgsl/bench_objects_gpu.wgsl): per object its position at t,
   a test against the view box (frustum culling in 2D), the visible ones appended to a list;
4. a render pass with ONE ``draw_indirect``: a quad per listed object, recomputed from its index.

So the CPU's work per frame does not depend on the object count. The list's order is the order the
atomics handed out slots; a depth value per object index keeps "later objects on top", as the other
modes draw them in order.

Mode ``gpu-compute-raster`` draws the same quads without the raster pipeline: on GH100 (H100/H200) the
few graphics units make a million 4x4-pixel quads a ~32 ms draw whoever animates them, while a compute
pass can rasterise such tiny axis-aligned quads itself: each visible object ``atomicMax``es its index
into the pixels whose centres it covers (the later object wins, as in draw order), and a second dispatch
turns indices into colours (and zeroes them for the next frame).
"""

from __future__ import annotations

import struct

import numpy as np
import wgpu

from wgpurender.bench.encoder import gpu_total
from wgpurender.bench.objects_data import BACKGROUND, FORMAT, HALF_SIZE, object_params
from wgpurender.core.shaders.shader_variants import specialise
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.device.shaders import create_shader_module, load_wgsl
from wgpurender.wgpu_path.device.targets import TARGET_USAGE, create_target
from wgpurender.wgpu_path.device.timing import PassTimer

SHADER = "bench_objects_gpu.wgsl"
MODE = "gpu-animated"
SPLAT_MODE = "gpu-compute-raster"  # the same, drawn by a compute rasteriser (cs_splat, cs_resolve) instead
WORKGROUP = 256
MAX_GROUPS_X = 65535
DEPTH_FORMAT = "depth32float"
PARAMS = struct.Struct("<4f2f2I")  # view (offset x, y, zoom, t), half size, count, row


def pack_colours(colours: np.ndarray) -> np.ndarray:
    """(count, 3) floats in [0, 1] -> (count,) uint32 rgba8 (unpack4x8unorm order: r in the low byte)."""
    k = np.round(np.clip(colours, 0.0, 1.0) * 255.0).astype(np.uint32)
    return k[:, 0] | (k[:, 1] << 8) | (k[:, 2] << 16) | np.uint32(255 << 24)


def dispatch_size(count: int) -> tuple[int, int]:
    """Workgroups (x, y) covering ``count`` invocations, x within the per-dimension limit."""
    groups = max(1, -(-count // WORKGROUP))
    x = min(groups, MAX_GROUPS_X)
    return x, -(-groups // x)


class GpuAnimatedRenderer:
    """``count`` quads animated, culled and drawn on the GPU (the runner protocol of frames.measure)."""

    def __init__(self, ctx: GPUContext, count: int, size: tuple[int, int] = (800, 600),
                 half_size: tuple[float, float] = HALF_SIZE,
                 view: tuple[float, float, float] = (0.0, 0.0, 1.0), mode: str = MODE) -> None:
        self.ctx, self.count, self.size, self.half_size, self.view = ctx, count, size, half_size, view
        self.mode = mode
        dev = self.device = ctx.device
        extra = wgpu.TextureUsage.STORAGE_BINDING if mode == SPLAT_MODE else 0
        self.target = create_target(ctx, size, FORMAT, usage=TARGET_USAGE | extra)
        self.depth = dev.create_texture(label="objects-depth", size=(size[0], size[1], 1), format=DEPTH_FORMAT,
                                        usage=wgpu.TextureUsage.RENDER_ATTACHMENT)
        self.timer = PassTimer(ctx)
        self.t = 0.0
        self.groups = dispatch_size(count)
        self._upload_objects()
        if mode == SPLAT_MODE:
            self._make_splat()
        else:
            self._make_pipelines()
        self._views = None

    def _upload_objects(self) -> None:
        dev, storage = self.device, wgpu.BufferUsage.STORAGE
        centres, phase, colours = object_params(self.count)
        phase_color = np.empty((self.count, 2), dtype=np.uint32)
        phase_color[:, 0] = phase.astype(np.float32).view(np.uint32)
        phase_color[:, 1] = pack_colours(colours)
        self.centres = dev.create_buffer_with_data(label="objects-centres", data=centres.astype(np.float32),
                                                   usage=storage)
        self.phase_color = dev.create_buffer_with_data(label="objects-phase-colour", data=phase_color, usage=storage)
        self.visible = dev.create_buffer(label="objects-visible", size=4 * self.count, usage=storage)
        self.indirect = dev.create_buffer_with_data(
            label="objects-draw", data=np.array([4, 0, 0, 0], dtype=np.uint32),
            usage=storage | wgpu.BufferUsage.INDIRECT | wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.COPY_SRC)
        self.params = dev.create_buffer(label="objects-params", size=PARAMS.size,
                                        usage=wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST)

    def _make_pipelines(self) -> None:
        dev = self.device
        cull = create_shader_module(dev, SHADER, specialise(load_wgsl(SHADER), {"cull"}, name=SHADER))
        draw = create_shader_module(dev, SHADER, specialise(load_wgsl(SHADER), {"draw"}, name=SHADER))
        self.cull_pipeline = dev.create_compute_pipeline(label="objects-cull", layout="auto",
                                                         compute={"module": cull, "entry_point": "cs_cull"})
        self.draw_pipeline = dev.create_render_pipeline(
            label="objects-gpu-draw", layout="auto",
            vertex={"module": draw, "entry_point": "vs_main", "buffers": []},
            primitive={"topology": "triangle-strip", "cull_mode": "none"},
            depth_stencil={"format": DEPTH_FORMAT, "depth_write_enabled": True, "depth_compare": "less"},
            multisample={"count": 1, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
            fragment={"module": draw, "entry_point": "fs_main", "targets": [{"format": FORMAT}]})
        shared = [self.params, self.centres, self.phase_color, self.visible]
        self.cull_group = self._group(self.cull_pipeline, [*shared, self.indirect])
        self.draw_group = self._group(self.draw_pipeline, shared)

    def _make_splat(self) -> None:
        """The compute rasteriser: one u32 per pixel (the winning object's index + 1), zero between frames."""
        dev = self.device
        w, h = self.size
        self.ids = dev.create_buffer(label="objects-pixel-ids", size=4 * w * h, usage=wgpu.BufferUsage.STORAGE)
        module = create_shader_module(dev, SHADER, specialise(load_wgsl(SHADER), {"splat"}, name=SHADER))
        self.splat_pipeline, self.resolve_pipeline = (dev.create_compute_pipeline(
            label=f"objects-{entry}", layout="auto", compute={"module": module, "entry_point": entry})
            for entry in ("cs_splat", "cs_resolve"))
        out = {"binding": 4, "resource": self.target.create_view()}
        self.splat_group = self._group(self.splat_pipeline, [self.params, self.centres, self.phase_color, self.ids],
                                       [out])
        self.resolve_group = dev.create_bind_group(layout=self.resolve_pipeline.get_bind_group_layout(0), entries=[
            {"binding": 2, "resource": {"buffer": self.phase_color, "offset": 0, "size": self.phase_color.size}},
            {"binding": 3, "resource": {"buffer": self.ids, "offset": 0, "size": self.ids.size}}, out])

    def _group(self, pipeline, buffers, extra=()) -> wgpu.GPUBindGroup:
        return self.device.create_bind_group(layout=pipeline.get_bind_group_layout(0), entries=[
            {"binding": i, "resource": {"buffer": b, "offset": 0, "size": b.size}} for i, b in enumerate(buffers)]
            + list(extra))

    # -- per frame ---------------------------------------------------------------------------
    def frame(self, readback: bool = False) -> tuple[float, float | None]:
        """(cpu_ms: uniform write + record + submit, gpu_ms of both passes or None); waits for the GPU."""
        f = run_frame(self.ctx, self.record, self.target, self.t, label="objects-gpu", read_back=readback,
                      timer=self.timer)
        return f.cpu_ms, gpu_total(f.gpu_ms)

    def untimed_cpu_ms(self, frames: int) -> list[float]:
        """CPU ms of ``frames`` frames as an application draws them: no timestamp queries, no readback."""
        timer, self.timer = self.timer, _NoTimer()
        try:
            return [run_frame(self.ctx, self.record, self.target, self.t, label="objects-gpu", read_back=False,
                              wait=True).cpu_ms for _ in range(frames)]
        finally:
            self.timer = timer

    def record(self, encoder, target, t: float) -> None:
        x, y = self.view[0], self.view[1]
        self.ctx.queue.write_buffer(self.params, 0, PARAMS.pack(x, y, self.view[2], t, *self.half_size, self.count,
                                                                self.groups[0] * WORKGROUP))
        if self.mode == SPLAT_MODE:
            self._record_splat(encoder)
            return
        encoder.clear_buffer(self.indirect, 4, 4)
        cp = encoder.begin_compute_pass(label="objects-cull", timestamp_writes=self.timer.writes("cull"))
        cp.set_pipeline(self.cull_pipeline)
        cp.set_bind_group(0, self.cull_group)
        cp.dispatch_workgroups(*self.groups, 1)
        cp.end()
        if self._views is None or self._views[0] is not target:
            self._views = (target, target.create_view(), self.depth.create_view())
        rp = encoder.begin_render_pass(
            label="objects-draw",
            color_attachments=[{"view": self._views[1], "load_op": "clear", "store_op": "store",
                                "clear_value": BACKGROUND}],
            depth_stencil_attachment={"view": self._views[2], "depth_clear_value": 1.0, "depth_load_op": "clear",
                                      "depth_store_op": "discard"},
            timestamp_writes=self.timer.writes("draw"))
        rp.set_pipeline(self.draw_pipeline)
        rp.set_bind_group(0, self.draw_group)
        rp.draw_indirect(self.indirect, 0)
        rp.end()

    def _record_splat(self, encoder) -> None:
        """One compute pass: splat every visible object, then resolve the pixels (two dispatches, two scopes)."""
        cp = encoder.begin_compute_pass(label="objects-splat", timestamp_writes=self.timer.writes("splat+resolve"))
        cp.set_pipeline(self.splat_pipeline)
        cp.set_bind_group(0, self.splat_group)
        cp.dispatch_workgroups(*self.groups, 1)
        cp.set_pipeline(self.resolve_pipeline)
        cp.set_bind_group(0, self.resolve_group)
        cp.dispatch_workgroups(-(-self.size[0] // 16), -(-self.size[1] // 16), 1)
        cp.end()

    def visible_count(self) -> int:
        """How many objects the last frame's culling kept (the indirect draw's instance count)."""
        return int(np.frombuffer(self.ctx.read_buffer(self.indirect, 4, 4), dtype=np.uint32)[0])

    def pixels(self) -> np.ndarray:
        from wgpurender.wgpu_path.device.targets import read_texture

        self.frame()
        return read_texture(self.ctx, self.target)


class _NoTimer:
    """A PassTimer that asks for no timestamps (``writes`` -> None)."""

    def writes(self, label: str) -> None:
        return None
