"""Many objects: N tiny quads, their per-object data delivered four ways, timed per frame.

Modes (the question each answers: what does one more object cost?):

- ``dynamic``: one uniform buffer holds every object's 32 bytes at 256-byte steps
  (min-uniform-buffer-offset-alignment); per object a ``set_bind_group`` with a
  dynamic offset and a ``draw`` (the course's UNIFORM_BUFFER_DYNAMIC);
- ``immediates``: per object ``set_immediates`` (push constants) and a ``draw``;
- ``instancing``: the objects in a per-instance vertex buffer, ONE draw for all;
- ``bundle``: the ``dynamic`` mode's draws recorded once into a render bundle and
  replayed per frame with ``execute_bundles`` (the recording is paid once, at set-up);
- ``gpu-animated`` (bench/objects_gpu.py): the same objects moved, culled and counted by the GPU,
  one indirect draw; the CPU writes 32 bytes a frame. The four modes above are the CPU-animated
  teaching baseline beside it.

Every frame the four CPU-animated modes move the objects (a numpy computation) and
upload them where the mode keeps them in a buffer. Quads are a few pixels wide,
so the cost measured is per object, not per pixel.
"""

from __future__ import annotations

import time

import numpy as np
import wgpu

from wgpurender.bench.encoder import gpu_total
from wgpurender.bench.frames import measure
from wgpurender.bench.objects_data import BACKGROUND, FORMAT, HALF_SIZE, object_params
from wgpurender.bench.report import Result, size_text
from wgpurender.core.errors import UserError
from wgpurender.core.shaders.shader_variants import specialise
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.device.shaders import create_shader_module, load_wgsl
from wgpurender.wgpu_path.device.targets import create_target
from wgpurender.wgpu_path.device.timing import PassTimer, Stats

SHADER = "bench_objects.wgsl"
MODES = ("dynamic", "immediates", "instancing", "bundle")
OBJECT_BYTES = 32  # rect + colour, two vec4f


def object_data(count: int, t: float, seed: int = 7, half_size: tuple[float, float] = HALF_SIZE) -> np.ndarray:
    """(count, 8) float32: quads at random places, drifting with ``t``, random opaque colours.

    The CPU-animated modes recompute this every frame (the teaching baseline); the GPU-animated mode
    (bench/objects_gpu.py) uploads :func:`object_params` once and computes the same drift in a shader.
    """
    centres, phase, colours = object_params(count, seed)
    data = np.empty((count, 8), dtype=np.float32)
    data[:, 0] = centres[:, 0] + 0.01 * np.sin(t + phase)
    data[:, 1] = centres[:, 1] + 0.01 * np.cos(t + phase)
    data[:, 2:4] = half_size
    data[:, 4:7] = colours
    data[:, 7] = 1.0
    return data


class ObjectsRenderer:
    """Draws ``count`` quads into an offscreen target using one ``mode``."""

    def __init__(self, ctx: GPUContext, mode: str, count: int, size: tuple[int, int] = (800, 600),
                 half_size: tuple[float, float] = HALF_SIZE) -> None:
        if mode not in MODES:
            raise UserError(f"unknown objects mode {mode!r}: choose one of {', '.join(MODES)}")
        if mode == "immediates" and not ctx.has("immediates"):
            raise UserError(f"{ctx.adapter.info['device']} lacks the 'immediates' feature: use another mode")
        self.ctx, self.mode, self.count, self.size = ctx, mode, count, size
        self.half_size = half_size
        self.device = ctx.device
        self.target = create_target(ctx, size, FORMAT)
        self.timer = PassTimer(ctx)
        self.t = 0.0
        self.stride = self.ctx.limit("min-uniform-buffer-offset-alignment") if mode in ("dynamic", "bundle") \
            else OBJECT_BYTES
        self._padded = np.zeros((count, self.stride // 4), dtype=np.float32)
        self.buffer = None
        if mode != "immediates":
            usage = (wgpu.BufferUsage.VERTEX if mode == "instancing" else wgpu.BufferUsage.UNIFORM) \
                | wgpu.BufferUsage.COPY_DST
            self.buffer = self.device.create_buffer(label=f"objects-{mode}", size=self.stride * count, usage=usage)
        self._make_pipeline()
        self.bundle = self._record_bundle() if mode == "bundle" else None

    # -- set-up --------------------------------------------------------------------------------
    def _variant(self) -> str:
        return {"dynamic": "uniform", "bundle": "uniform", "instancing": "instanced"}.get(self.mode, self.mode)

    def _make_pipeline(self) -> None:
        dev = self.device
        variant = self._variant()
        source = specialise(load_wgsl(SHADER), {variant}, name=SHADER)
        module = create_shader_module(dev, SHADER, source)
        layouts = []
        if variant == "uniform":
            bgl = dev.create_bind_group_layout(entries=[{
                "binding": 0, "visibility": wgpu.ShaderStage.VERTEX,
                "buffer": {"type": "uniform", "has_dynamic_offset": True, "min_binding_size": OBJECT_BYTES}}])
            layouts.append(bgl)
            self.group = dev.create_bind_group(layout=bgl, entries=[
                {"binding": 0, "resource": {"buffer": self.buffer, "offset": 0, "size": OBJECT_BYTES}}])
        layout = dev.create_pipeline_layout(bind_group_layouts=layouts,
                                            immediate_size=OBJECT_BYTES if variant == "immediates" else 0)
        buffers = []
        if variant == "instanced":
            buffers = [{"array_stride": OBJECT_BYTES, "step_mode": "instance", "attributes": [
                {"shader_location": 0, "format": "float32x4", "offset": 0},
                {"shader_location": 1, "format": "float32x4", "offset": 16}]}]
        self.pipeline = dev.create_render_pipeline(
            label=f"objects-{self.mode}", layout=layout,
            vertex={"module": module, "entry_point": "vs_main", "buffers": buffers},
            primitive={"topology": "triangle-strip", "cull_mode": "none"},
            depth_stencil=None,
            multisample={"count": 1, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": FORMAT}]},
        )

    def _record_bundle(self) -> wgpu.GPURenderBundle:
        enc = self.device.create_render_bundle_encoder(color_formats=[FORMAT])
        self._draw_dynamic(enc)
        return enc.finish()

    # -- per frame -------------------------------------------------------------------------------
    def _draw_dynamic(self, rp) -> None:
        rp.set_pipeline(self.pipeline)
        stride, group = self.stride, self.group
        for k in range(self.count):
            rp.set_bind_group(0, group, [k * stride])
            rp.draw(4)

    def _draw_immediates(self, rp, data: np.ndarray) -> None:
        rp.set_pipeline(self.pipeline)
        for k in range(self.count):
            rp.set_immediates(0, data, k * OBJECT_BYTES, OBJECT_BYTES)
            rp.draw(4)

    def upload(self, data: np.ndarray) -> None:
        if self.buffer is None:
            return
        if self.stride == OBJECT_BYTES:
            self.ctx.queue.write_buffer(self.buffer, 0, data)
        else:
            self._padded[:, :8] = data
            self.ctx.queue.write_buffer(self.buffer, 0, self._padded)

    def frame(self, readback: bool = False) -> tuple[float, float | None]:
        """(cpu_ms: data + upload + record + submit, gpu_ms of the pass or None); waits for the GPU."""
        f = run_frame(self.ctx, self.record, self.target, self.t, label=f"objects-{self.mode}", read_back=readback,
                      timer=self.timer)
        return f.cpu_ms, gpu_total(f.gpu_ms)

    def record(self, encoder, target, t: float) -> None:
        data = object_data(self.count, t, half_size=self.half_size)
        self.upload(data)
        rp = encoder.begin_render_pass(
            color_attachments=[{"view": target.create_view(), "load_op": "clear", "store_op": "store",
                                "clear_value": BACKGROUND}],
            timestamp_writes=self.timer.writes(self.mode))
        if self.mode == "dynamic":
            self._draw_dynamic(rp)
        elif self.mode == "immediates":
            self._draw_immediates(rp, data)
        elif self.mode == "instancing":
            rp.set_pipeline(self.pipeline)
            rp.set_vertex_buffer(0, self.buffer)
            rp.draw(4, self.count)
        else:
            rp.execute_bundles([self.bundle])
        rp.end()

    def pixels(self) -> np.ndarray:
        from wgpurender.wgpu_path.device.targets import read_texture

        self.frame()
        return read_texture(self.ctx, self.target)


def bench_objects(ctx: GPUContext, counts: list[int], modes: list[str], frames: int,
                  per_draw_limit: int | None = None, size: tuple[int, int] = (800, 600),
                  log=print, limits: dict[str, int] | None = None) -> list[Result]:
    """Each mode at each count. Modes that issue one call per object skip counts above ``per_draw_limit``;
    ``limits``: the largest count per mode (a mode absent from it has none). Mode ``gpu-animated`` is
    bench/objects_gpu.py's renderer (animation, culling and the draw's instance count on the GPU)."""
    from wgpurender.bench.objects_gpu import MODE as GPU_MODE
    from wgpurender.bench.objects_gpu import SPLAT_MODE, GpuAnimatedRenderer

    out: list[Result] = []
    for count in counts:
        for mode in modes:
            if mode == "immediates" and not ctx.has("immediates"):
                continue
            if per_draw_limit is not None and mode in ("dynamic", "immediates") and count > per_draw_limit:
                log(f"  objects: {mode} at {count} skipped (over the per-draw limit {per_draw_limit} here)")
                continue
            if limits and count > limits.get(mode, count):
                log(f"  objects: {mode} at {count} skipped (over this mode's limit {limits[mode]} here)")
                continue
            start = time.perf_counter()
            if mode in (GPU_MODE, SPLAT_MODE):
                renderer = GpuAnimatedRenderer(ctx, count, size, mode=mode)
            else:
                renderer = ObjectsRenderer(ctx, mode, count, size)
            setup_ms = (time.perf_counter() - start) * 1e3
            n = frames if count <= 10_000 else max(3, frames // 3)
            samples = measure(renderer, n, warmup=1)
            case = f"{mode}/{count}"
            out += samples.results("objects", case, "wgpu", size, note="")
            if mode in (GPU_MODE, SPLAT_MODE):
                out.append(Result.of("objects", case, "wgpu", size_text(size), "cpu_ms:untimed",
                                     Stats.of(renderer.untimed_cpu_ms(n)),
                                     "record + submit without timestamp queries (as an application draws it)"))
            out.append(Result("objects", case, "wgpu", size_text(size), "setup_ms", setup_ms, setup_ms, setup_ms, 1,
                              "pipeline + buffers (+ bundle recording)"))
            log(f"  objects: {case}: frame {np.median(samples.frame):.2f} ms, cpu {np.median(samples.cpu):.2f} ms")
            del renderer
    return out
