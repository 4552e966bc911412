"""Post-processing costs: each effect, the post pass taken apart, and wgpu against the raw subpass.

- ``effects``: every effect of wgpurender.wgpu_path.post as one pass (GPU timestamps of that
  pass alone; CPU time to encode and submit it), reading an rgba16float image (the
  chain's intermediate format) and writing the output format;
- ``probe``: a full-screen copy pass with one knob changed at a time, to find what
  makes a trivial post pass expensive: the source and target formats, sampler vs
  textureLoad, one triangle vs a quad, load_op clear vs load, and an empty pass
  (clear + store, no draw) for the floor;
- ``msaa-post``: the stage of that name on both paths: the raw path's one render pass
  with two subpasses (the grey effect reads the resolve as an input attachment) against
  the wgpu stage's MSAA triangle pass followed by a second render pass sampling the
  resolved texture (wgpurender/wgpu_path/stages/msaa_post.py says why wgpu needs it).
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass

import wgpu

from wgpurender.bench.encoder import gpu_total, timed_frame
from wgpurender.bench.frames import RawStageRunner, Samples, WgpuStageRunner, measure
from wgpurender.bench.report import Result
from wgpurender.core.course.formats import BYTES_PER_PIXEL
from wgpurender.core.shaders.shader_variants import specialise
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module, load_wgsl
from wgpurender.wgpu_path.device.targets import create_target
from wgpurender.wgpu_path.device.timing import PassTimer, Stats

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
    """One effect step (wgpurender.core.course.effects) as its own fragment pass."""

    def __init__(self, ctx: GPUContext, step, size: tuple[int, int], src_fmt: str, dst_fmt: str) -> None:
        from wgpurender.wgpu_path.post import PostChain

        super().__init__(ctx, f"post-{step.effect}")
        self.chain = PostChain([step], intermediate_format=src_fmt)
        self.source = _source(ctx, size, src_fmt)
        self.target = create_target(ctx, size, dst_fmt)

    def encode_pass(self, encoder) -> None:
        self.chain.run(self.ctx, encoder, self.source, self.target)


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


def bench_effects(ctx: GPUContext, size: tuple[int, int], frames: int) -> list[Result]:
    from wgpurender.wgpu_path.post import EFFECTS, create_effect

    out = []
    for name in sorted(EFFECTS):
        dst = "rgba8unorm" if name == "srgb" else "rgba8unorm-srgb"
        runner = EffectRunner(ctx, create_effect(name), size, "rgba16float", dst)
        out += measure(runner, frames).results("post-effects", name, "wgpu", size, note=f"rgba16float -> {dst}")
    return out


def bench_probes(ctx: GPUContext, size: tuple[int, int], frames: int) -> list[Result]:
    out = []
    for probe in PROBES:
        out += measure(ProbeRunner(ctx, probe, size), frames).results("post-probe", probe.name, "wgpu", size)
    return out


def msaa_post_traffic(size: tuple[int, int], fmt: str = "rgba8unorm-srgb") -> dict[str, int]:
    """Bytes that each path's load/store ops and reads declare must go through memory, per frame.

    Both: the 4-sample image is cleared and discarded (never stored), the output stored once. raw: the
    resolve attachment is never stored (storeOp DONT_CARE, TRANSIENT) and subpass 1 reads it as an input
    attachment, which a tiling GPU serves from tile memory: nothing else. wgpu: the resolve target must be
    stored (the next pass samples it) and read back by the post pass: two more full images. On a desktop
    GPU or lavapipe the raw resolve lives in memory too, so the declared saving is a tiler's, not theirs.
    """
    image = size[0] * size[1] * BYTES_PER_PIXEL[fmt]
    return {"raw": image, "wgpu": 3 * image}


def msaa_post_traffic_results(size: tuple[int, int]) -> list[Result]:
    s = f"{size[0]}x{size[1]}"
    notes = {"raw": "output store only (resolve never stored, input attachment read from tile memory)",
             "wgpu": "resolve stored + sampled by pass 2 + output store"}
    return [Result("msaa-post", "msaa-post", path, s, "declared_mb", b / 1e6, b / 1e6, b / 1e6, 1, notes[path])
            for path, b in msaa_post_traffic(size).items()]


def _interleaved(runners: dict[tuple[str, str], object], frames: int) -> dict[tuple[str, str], Samples]:
    """One frame of each runner per round, the order reversed every other round: on a loaded machine the
    load drifts over seconds, so measuring one runner after the other would compare different loads."""
    for runner in runners.values():
        measure(runner, 0, warmup=2)
    out = {key: Samples() for key in runners}
    for i in range(frames):
        for key in (list(runners) if i % 2 == 0 else list(reversed(runners))):
            sample = measure(runners[key], 1, warmup=0)
            out[key].frame += sample.frame
            out[key].cpu += sample.cpu
            out[key].gpu += sample.gpu
    return out


def _paired_increment(samples: dict[tuple[str, str], Samples], path: str, size: tuple[int, int]) -> list[Result]:
    """The post step's GPU cost: msaa-post minus msaa alone, frame by frame within a round (paired), so
    that the load of that moment cancels; its median and spread."""
    with_post, alone = samples[("msaa-post", path)].gpu, samples[("msaa alone", path)].gpu
    if not with_post or len(with_post) != len(alone):
        return []
    stats = Stats.of([a - b for a, b in zip(with_post, alone, strict=True)])
    return [Result("msaa-post", "post step (paired difference)", path, f"{size[0]}x{size[1]}", "gpu_ms",
                   stats.median, stats.p10, stats.p90, stats.n, "msaa-post minus msaa alone, same round")]


def bench_msaa_post(ctx: GPUContext, size: tuple[int, int], frames: int, raw: bool = True) -> list[Result]:
    """msaa-post on both paths, plus the msaa stage alone on both, so the post step's cost can be read off
    (interleaved frame by frame); and the memory traffic each path declares (:func:`msaa_post_traffic`)."""
    notes = {("msaa-post", "wgpu"): "msaa pass + post pass", ("msaa-post", "raw"): "one render pass, two subpasses"}
    with ExitStack() as stack:
        runners = {("msaa-post", "wgpu"): WgpuStageRunner(ctx, "msaa-post", size),
                   ("msaa alone", "wgpu"): WgpuStageRunner(ctx, "msaa", size)}
        if raw:
            runners[("msaa-post", "raw")] = stack.enter_context(RawStageRunner("msaa-post", size))
            runners[("msaa alone", "raw")] = stack.enter_context(RawStageRunner("msaa", size))
        samples = _interleaved(runners, frames)
    out = []
    for (case, path), sample in samples.items():
        out += sample.results("msaa-post", case, path, size, note=notes.get((case, path), ""))
    for path in ("wgpu", "raw") if raw else ("wgpu",):
        out += _paired_increment(samples, path, size)
    return out + msaa_post_traffic_results(size)
