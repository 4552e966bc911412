"""Post-processing costs: each effect, the post pass taken apart, and wgpu against the raw subpass.

- ``effects``: every effect of wgpurender.post as one pass (GPU timestamps of that
  pass alone; CPU time to encode and submit it), reading an rgba16float image (the
  chain's intermediate format) and writing the output format;
- ``probe``: a full-screen copy pass with one knob changed at a time, to find what
  makes a trivial post pass expensive: the source and target formats, sampler vs
  textureLoad, one triangle vs a quad, load_op clear vs load, and an empty pass
  (clear + store, no draw) for the floor;
- ``msaa-post``: the raw path's one-render-pass, two-subpass stage (the grey effect
  reads the resolve as an input attachment) against wgpu's MSAA triangle pass
  followed by the grayscale effect as a second render pass.
"""

from __future__ import annotations

from dataclasses import dataclass

import wgpu

from ..gpu import GPUContext
from ..shader_variants import specialise
from ..shaders import create_shader_module, load_wgsl
from ..targets import create_target
from ..timing import PassTimer
from .encoder import gpu_total, timed_frame
from .frames import RawStageRunner, WgpuStageRunner, measure
from .report import Result

PROBE_SHADER = "bench_post_probe.wgsl"
SOURCE_USAGE = wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.TEXTURE_BINDING


def _source(ctx: GPUContext, size: tuple[int, int], fmt: str) -> wgpu.GPUTexture:
    """A source image with content (a cleared colour is enough: the shaders do not branch on it)."""
    tex = ctx.device.create_texture(label=f"post-src-{fmt}", size=(size[0], size[1], 1), format=fmt,
                                    usage=SOURCE_USAGE)
    enc = ctx.device.create_command_encoder()
    rp = enc.begin_render_pass(color_attachments=[{"view": tex.create_view(), "load_op": "clear",
                                                   "store_op": "store", "clear_value": (0.6, 0.3, 0.2, 1.0)}])
    rp.end()
    ctx.queue.submit([enc.finish()])
    return tex


class _PassRunner:
    """One frame = whatever ``encode_pass`` records, timed; the runner protocol of frames.measure."""

    def __init__(self, ctx: GPUContext, label: str) -> None:
        self.ctx = ctx
        self.label = label
        self.timer = PassTimer(ctx)

    def encode_pass(self, encoder) -> None:
        raise NotImplementedError

    def frame(self, readback: bool = False) -> tuple[float, float | None]:
        cpu_ms, gpu = timed_frame(self.ctx, lambda encoder, target, t: self.encode_pass(encoder), self.target,
                                  self.timer, self.label)
        return cpu_ms, gpu_total(gpu)


class EffectRunner(_PassRunner):
    def __init__(self, ctx: GPUContext, effect, size: tuple[int, int], src_fmt: str, dst_fmt: str) -> None:
        super().__init__(ctx, f"post-{effect.name}")
        self.effect = effect
        self.source = _source(ctx, size, src_fmt)
        self.target = create_target(ctx, size, dst_fmt)

    def encode_pass(self, encoder) -> None:
        self.effect.encode(self.ctx.device, encoder, self.source, self.target)


@dataclass(frozen=True)
class Probe:
    """One configuration of the copy pass."""

    name: str
    src: str = "rgba16float"
    dst: str = "rgba8unorm-srgb"
    sampler: bool = False
    quad: bool = False
    load_op: str = "clear"
    draw: bool = True


PROBES = (
    Probe("copy (textureLoad, triangle, clear): rgba16float -> rgba8unorm-srgb"),
    Probe("empty pass (clear + store, no draw)", draw=False),
    Probe("src rgba8unorm-srgb", src="rgba8unorm-srgb"),
    Probe("src rgba8unorm", src="rgba8unorm", dst="rgba8unorm"),
    Probe("dst rgba8unorm", dst="rgba8unorm"),
    Probe("dst rgba16float", dst="rgba16float"),
    Probe("sampler instead of textureLoad", sampler=True),
    Probe("quad instead of triangle", quad=True),
    Probe("load_op load instead of clear", load_op="load"),
)


class ProbeRunner(_PassRunner):
    def __init__(self, ctx: GPUContext, probe: Probe, size: tuple[int, int]) -> None:
        super().__init__(ctx, "probe")
        dev = ctx.device
        self.probe = probe
        self.source = _source(ctx, size, probe.src)
        self.target = create_target(ctx, size, probe.dst)
        flags = {name for name, on in (("sampler", probe.sampler), ("quad", probe.quad)) if on}
        module = create_shader_module(dev, PROBE_SHADER, specialise(load_wgsl(PROBE_SHADER), flags,
                                                                    name=PROBE_SHADER))
        self.pipeline = dev.create_render_pipeline(
            label="post-probe", layout="auto",
            vertex={"module": module, "entry_point": "vs_main", "buffers": []},
            primitive={"topology": "triangle-list", "cull_mode": "none"},
            depth_stencil=None, multisample={"count": 1, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": probe.dst}]})
        entries = [{"binding": 0, "resource": self.source.create_view()}]
        if probe.sampler:
            entries.append({"binding": 1, "resource": dev.create_sampler(mag_filter="linear", min_filter="linear")})
        self.group = dev.create_bind_group(layout=self.pipeline.get_bind_group_layout(0), entries=entries)
        self.view = self.target.create_view()

    def encode_pass(self, encoder) -> None:
        p = self.probe
        rp = encoder.begin_render_pass(color_attachments=[{
            "view": self.view, "load_op": p.load_op, "store_op": "store", "clear_value": (0, 0, 0, 0)}])
        if p.draw:
            rp.set_pipeline(self.pipeline)
            rp.set_bind_group(0, self.group)
            rp.draw(6 if p.quad else 3)
        rp.end()


class WgpuMsaaPostRunner(WgpuStageRunner):
    """wgpu's counterpart of the raw msaa-post stage: the msaa stage into an image, then grayscale."""

    def __init__(self, ctx: GPUContext, size: tuple[int, int], scene_format: str = "rgba8unorm-srgb") -> None:
        from ..post import create_effect

        super().__init__(ctx, "msaa", size)
        self.name = "msaa-post"
        self.scene = _source(ctx, size, scene_format)
        self.effect = create_effect("grayscale", amount=1.0)

    def record(self, encoder, target, t: float) -> None:
        self.stage.record(encoder, self.scene, t)
        self.effect.encode(self.ctx.device, encoder, self.scene, target)


def bench_effects(ctx: GPUContext, size: tuple[int, int], frames: int) -> list[Result]:
    from ..post import EFFECTS

    out = []
    for name, cls in sorted(EFFECTS.items()):
        dst = "rgba8unorm" if name == "srgb" else "rgba8unorm-srgb"
        runner = EffectRunner(ctx, cls(), size, "rgba16float", dst)
        out += measure(runner, frames).results("post-effects", name, "wgpu", size, note=f"rgba16float -> {dst}")
    return out


def bench_probes(ctx: GPUContext, size: tuple[int, int], frames: int) -> list[Result]:
    out = []
    for probe in PROBES:
        out += measure(ProbeRunner(ctx, probe, size), frames).results("post-probe", probe.name, "wgpu", size)
    return out


def bench_msaa_post(ctx: GPUContext, size: tuple[int, int], frames: int, raw: bool = True) -> list[Result]:
    """msaa-post on both paths, plus the msaa stage alone on both, so the post increment can be read off."""
    out = measure(WgpuMsaaPostRunner(ctx, size), frames).results(
        "msaa-post", "msaa-post", "wgpu", size, note="msaa pass + grayscale pass")
    out += measure(WgpuStageRunner(ctx, "msaa", size), frames).results("msaa-post", "msaa alone", "wgpu", size)
    if raw:
        with RawStageRunner("msaa-post", size) as runner:
            out += measure(runner, frames).results("msaa-post", "msaa-post", "raw", size,
                                                   note="one render pass, two subpasses")
        with RawStageRunner("msaa", size) as runner:
            out += measure(runner, frames).results("msaa-post", "msaa alone", "raw", size)
    return out
