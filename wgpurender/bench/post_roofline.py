"""Post passes against the memory roofline: bytes moved, time, GB/s, and % of a copy moving the same bytes.

For each way the plan can run a scene's post chain (fragment or compute path, fused or one pass per
effect), the scene is drawn once at the requested size, then the post passes alone are timed with GPU
timestamps (median of ``frames``). Each pass's bytes are the plan's compulsory traffic (each texel of
its input read once, each texel of its output written once, FXAA's mask included): what the pass moves
at best. The roofline is measured in the same run: a compute kernel that copies a storage buffer of
half the pass's bytes into another (so it reads and writes the same number of bytes as the pass),
timed the same way. "% of copy" = the copy's time / the pass's time. Each variant is timed again with the
knob post_intermediate = rgba8unorm (:data:`INTERMEDIATES`): the accuracy it costs is in
tests/test_post_intermediate.py, against float64.

A compute pass into a swapchain-like output (knob ``output_storage = off``) also copies its scratch into the
output (``copy_texture_to_texture`` takes no timestamps): its row gives the dispatch's time and bytes, and the
copy's bytes are listed apart. An offscreen ``-srgb`` output is written directly as its rgba8unorm twin: no copy.

Run it where the question is (NVIDIA, 3840x2160): ``wgpurender bench post-roofline --size 3840x2160``
(final.toml and final_subpass.toml, whose fused chain is a single per-pixel pass).
"""

from __future__ import annotations

import csv
import dataclasses
import io
import statistics
from dataclasses import dataclass
from pathlib import Path

import wgpu

from wgpurender.core.errors import UserError
from wgpurender.core.plan import BYTES_PER_PIXEL, PostPass, resolve_plan
from wgpurender.core.plan.dispatch import shape_text
from wgpurender.core.scene import load_scene
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.timing import PassTimer, wall_time

VARIANTS = (("fragment", False), ("fragment", True), ("compute", False), ("compute", True))
# the knob post_intermediate's settings timed for each variant ("auto": the scene image's format, today's image);
# a chain that stores nothing between passes refuses a set knob, and that variant is left out (one line in the .md)
INTERMEDIATES = ("auto", "rgba8unorm", "rgba8unorm-srgb", "none")
COPY_WGSL = """
@group(0) @binding(0) var<storage, read> src: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> dst: array<vec4<u32>>;

@compute @workgroup_size(256)
fn cs_main(@builtin(global_invocation_id) id: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = id.x + id.y * groups.x * 256u;
    if i < arrayLength(&src) {
        dst[i] = src[i];
    }
}
"""


@dataclass(frozen=True)
class PassTime:
    variant: str
    effects: str
    path: str
    bytes_moved: int
    ms: float
    copy_ms: float
    copy_bytes: int = 0  # a compute pass's scratch -> output copy (not timed)
    chain_wall_ms: float = float("nan")  # the whole chain (a swept pass: that pass), submit + wait, by wall clock
    intermediate: str = "auto"  # the knob post_intermediate of this row's plan

    @property
    def gbps(self) -> float:
        return self.bytes_moved / (self.ms * 1e6) if self.ms > 0 else float("nan")

    @property
    def copy_gbps(self) -> float:
        return self.bytes_moved / (self.copy_ms * 1e6) if self.copy_ms > 0 else float("nan")

    @property
    def percent_of_copy(self) -> float:
        return 100.0 * self.copy_ms / self.ms if self.ms > 0 else float("nan")


def dispatch_bytes(p: PostPass, size: tuple[int, int]) -> tuple[int, int]:
    """(bytes the timed pass moves, bytes of the untimed copy after it)."""
    if not p.copy_to:
        return p.bytes_moved, 0
    copy = size[0] * size[1] * (BYTES_PER_PIXEL[p.output_format] * 2)
    return p.bytes_moved - copy, copy


class CopyKernel:
    """A compute copy of ``n_bytes / 2`` bytes (read + write = ``n_bytes``), timed by timestamps."""

    def __init__(self, ctx: GPUContext) -> None:
        self.ctx = ctx
        module = ctx.device.create_shader_module(label="roofline-copy", code=COPY_WGSL)
        self.pipeline = ctx.device.create_compute_pipeline(label="roofline-copy", layout="auto",
                                                           compute={"module": module, "entry_point": "cs_main"})
        self.timer = PassTimer(ctx, max_passes=1)
        self._times: dict[int, float] = {}

    def ms(self, n_bytes: int, frames: int) -> float:
        if n_bytes not in self._times:
            self._times[n_bytes] = self._measure(n_bytes, frames)
        return self._times[n_bytes]

    def _measure(self, n_bytes: int, frames: int) -> float:
        half = max(16, n_bytes // 2 // 16 * 16)
        usage = wgpu.BufferUsage.STORAGE
        src = self.ctx.device.create_buffer(size=half, usage=usage)
        dst = self.ctx.device.create_buffer(size=half, usage=usage)
        group = self.ctx.device.create_bind_group(layout=self.pipeline.get_bind_group_layout(0), entries=[
            {"binding": 0, "resource": {"buffer": src, "offset": 0, "size": half}},
            {"binding": 1, "resource": {"buffer": dst, "offset": 0, "size": half}}])
        groups = -(-(half // 16) // 256)
        gx = min(groups, 65535)
        gy = -(-groups // gx)
        samples = []
        for _ in range(frames + 2):  # two warm-up runs
            self.timer.reset()
            encoder = self.ctx.device.create_command_encoder()
            cp = encoder.begin_compute_pass(timestamp_writes=self.timer.writes("copy"))
            cp.set_pipeline(self.pipeline)
            cp.set_bind_group(0, group)
            cp.dispatch_workgroups(gx, gy, 1)
            cp.end()
            self.timer.resolve(encoder)
            self.ctx.queue.submit([encoder.finish()])
            samples.append(self.timer.read().get("copy", float("nan")))
        return statistics.median(samples[2:])


def time_variant(ctx: GPUContext, scene, size: tuple[int, int], path: str, fuse: bool, frames: int,
                 copy: CopyKernel, intermediate: str = "auto") -> list[PassTime]:
    from wgpurender.wgpu_path.scene import SceneRenderer, render_frame

    plan = resolve_plan(scene, ctx.adapter_facts(), size=size, post_path=path, post_fuse=fuse,
                        post_intermediate=intermediate)
    renderer = SceneRenderer(ctx, scene, plan)
    target = renderer.create_output()  # the plan's output texture (a compute path's -srgb twin included)
    render_frame(ctx, renderer, target)  # the scene image the chain reads, and every pipeline made
    timer = PassTimer(ctx, max_passes=len(plan.post_passes))
    samples: list[dict[str, float]] = []
    for _ in range(frames + 2):
        timer.reset()
        encoder = ctx.device.create_command_encoder()
        renderer.chain.run(encoder, {**renderer.attachments, "output": target}, timer=timer)
        timer.resolve(encoder)
        ctx.queue.submit([encoder.finish()])
        samples.append(timer.read())
    samples = samples[2:]
    wall = wall_time(lambda: _chain_once(ctx, renderer, target), warmup=1, repeats=frames).median
    variant = f"{path}, {'fused' if fuse else 'unfused'}" + ("" if intermediate == "auto" else f", {intermediate}")
    out = []
    for p in plan.post_passes:
        ms = statistics.median(s.get(f"post:{p.effect}", float("nan")) for s in samples)
        moved, copied = dispatch_bytes(p, size)
        out.append(PassTime(variant, p.effect, p.path, moved, ms, copy.ms(moved, frames), copied, wall,
                            intermediate))
    return out


def _pass_once(ctx: GPUContext, runner, source, target) -> None:
    encoder = ctx.device.create_command_encoder()
    runner.encode(encoder, source, target)
    ctx.queue.submit([encoder.finish()])
    ctx.wait_idle()


def _chain_once(ctx: GPUContext, renderer, target) -> None:
    encoder = ctx.device.create_command_encoder()
    renderer.chain.run(encoder, {**renderer.attachments, "output": target})
    ctx.queue.submit([encoder.finish()])
    ctx.wait_idle()


# (workgroup x, workgroup y, rows per invocation) tried by --shapes on the fused compute passes
SHAPES = ((8, 8, 1), (16, 16, 1), (32, 8, 1), (64, 4, 1), (256, 1, 1), (8, 8, 2), (16, 8, 2), (16, 16, 2),
          (32, 8, 2), (8, 8, 4), (32, 8, 4), (64, 1, 4), (128, 1, 2))


def sweep_cases(p: PostPass, shapes) -> list[tuple[tuple[int, int, int], str]]:
    """(shape, tile) dispatched by the sweep for pass ``p``: every shape; an FXAA pass (tiled by the plan or not)
    through each workgroup tile it can take (where the tile fits in workgroup memory), over an edge list
    ("edges": wgpurender/bench/fxaa_variants/edge_list.py) and untiled (""), the same image."""
    from wgpurender.core.plan.dispatch import TILE_KINDS, tile_fits
    from wgpurender.wgpu_path.post.shaders import tileable

    cases = [(shape, kind) for kind in TILE_KINDS if tileable(p, kind) for shape in shapes if tile_fits(shape, kind)]
    edges = [(shape, "edges") for shape in shapes] if tileable(p) else []
    return cases + edges + [(shape, "") for shape in shapes]


TILE_LABELS = {"texels": ", tiled", "luma": ", luma tile", "edges": ", edge list", "": ", untiled"}


def shape_sweep(ctx: GPUContext, scene, size: tuple[int, int], frames: int, copy: CopyKernel,
                shapes=SHAPES, intermediate: str = "auto") -> list[PassTime]:
    """The fused compute chain's passes, each dispatched with every shape (:func:`sweep_cases`), same run;
    ``intermediate``: the knob post_intermediate of the chain swept."""
    from wgpurender.bench.fxaa_variants.edge_list import EdgeListPass
    from wgpurender.wgpu_path.post.passes import ComputePass
    from wgpurender.wgpu_path.post.shaders import tileable
    from wgpurender.wgpu_path.scene import SceneRenderer, render_frame

    plan = resolve_plan(scene, ctx.adapter_facts(), size=size, post_path="compute", post_fuse=True,
                        post_intermediate=intermediate)
    knob = "" if intermediate == "auto" else f", {intermediate}"
    renderer = SceneRenderer(ctx, scene, plan)
    target = renderer.create_output()  # the plan's output texture (a compute path's -srgb twin included)
    render_frame(ctx, renderer, target)
    textures = {**renderer.attachments, "output": target}
    rows = []
    for p in plan.post_passes:
        moved, copied = dispatch_bytes(p, size)
        for shape, tiled in sweep_cases(p, shapes):
            edges = tiled == "edges"
            runner = EdgeListPass(ctx.device, p, shape) if edges else ComputePass(ctx.device, p, shape, tiled)
            timer = PassTimer(ctx, max_passes=1)
            samples = []
            for _ in range(frames + 2):
                timer.reset()
                encoder = ctx.device.create_command_encoder()
                runner.encode(encoder, textures[p.input], textures[p.output], timestamp_writes=timer.writes("pass"))
                timer.resolve(encoder)
                ctx.queue.submit([encoder.finish()])
                samples.append(timer.read().get("pass", float("nan")))
            ms = statistics.median(samples[2:])
            wall = wall_time(lambda r=runner, p=p: _pass_once(ctx, r, textures[p.input], textures[p.output]),
                             warmup=1, repeats=frames).median  # lavapipe's timestamps do not bracket a dispatch
            how = TILE_LABELS[tiled] if tileable(p) else ""
            rows.append(PassTime(f"compute, fused{knob}, shape {shape_text(shape)}{how}", p.effect,
                                 "compute", moved, ms, copy.ms(moved, frames), copied, wall, intermediate))
    return rows


def run_roofline(ctx: GPUContext, scene_path: Path, size: tuple[int, int], frames: int,
                 shapes: bool = False, sweep=None) -> list[PassTime]:
    """Every variant's rows; with ``shapes``, the fused compute passes dispatched with each shape of ``sweep``
    (default :data:`SHAPES`)."""
    scene = load_scene(scene_path)
    if not resolve_plan(scene, ctx.adapter_facts(), size=size).post_passes:  # else a query set of 0 timestamps:
        raise UserError(f"{scene_path} has no [[post]] effects: post-roofline times a post chain; give a scene "
                        "with one, e.g. final.toml")  # a validation error's traceback
    copy = CopyKernel(ctx)
    rows: list[PassTime] = []
    for intermediate in INTERMEDIATES:
        for path, fuse in VARIANTS:
            try:
                rows += time_variant(ctx, scene, size, path, fuse, frames, copy, intermediate)
            except UserError:
                if intermediate == "auto":
                    raise
                # the chain runs as one pass on this variant: nothing stored between passes, nothing to time
    if shapes:
        rows += shape_sweep(ctx, scene, size, frames, copy, sweep or SHAPES)
        try:  # the one-pass chain (tonemap recomputed in FXAA) is the most ALU-bound: its shape may matter most
            rows += shape_sweep(ctx, scene, size, frames, copy, sweep or SHAPES, intermediate="none")
        except UserError:
            pass  # no FXAA pass to recompute into: the auto sweep is the whole story
    return rows


def markdown(rows: list[PassTime], ctx: GPUContext, scene_path: Path, size: tuple[int, int], frames: int,
             command: str) -> str:
    lines = [f"# Post passes against the memory roofline ({size[0]}x{size[1]})", "",
             f"- adapter: {ctx.describe()}", f"- scene: {scene_path}", f"- command: `{command}`",
             f"- GPU timestamps, median of {frames} frames; copy = a compute kernel moving the same bytes, "
             "same run", "",
             "| variant | pass | path | MB moved | ms | GB/s | copy ms | copy GB/s | % of copy |",
             "|---|---|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        extra = f" (+{r.copy_bytes / 1e6:.1f} MB copy, untimed)" if r.copy_bytes else ""
        lines.append(f"| {r.variant} | {r.effects}{extra} | {r.path} | {r.bytes_moved / 1e6:.1f} | {r.ms:.3f} | "
                     f"{r.gbps:.1f} | {r.copy_ms:.3f} | {r.copy_gbps:.1f} | {r.percent_of_copy:.0f}% |")
    lines.append("")
    for variant in dict.fromkeys(r.variant for r in rows):
        mine = [r for r in rows if r.variant == variant]
        total_ms = sum(r.ms for r in mine)
        total_bytes = sum(r.bytes_moved for r in mine)
        lines.append(f"- {variant}: {len(mine)} pass(es), {total_bytes / 1e6:.1f} MB, {total_ms:.3f} ms by "
                     f"timestamps ({total_bytes / (total_ms * 1e6) if total_ms else float('nan'):.1f} GB/s); "
                     f"{'the pass' if 'shape' in variant else 'whole chain'} by wall clock (submit + wait) "
                     f"{mine[0].chain_wall_ms:.3f} ms; "
                     f"{chain_ratio(mine):.2f}x a copy of the same bytes" + _against_auto(rows, variant, mine))
    lines += best_shapes(rows)
    timed = {r.variant for r in rows}
    names = [f"{p}, {'fused' if f else 'unfused'}" for p, f in VARIANTS]
    lines += [f"- {v}, {k}: left out (this chain stores no image between passes, or none it could recompute)"
              for k in INTERMEDIATES[1:] for v in names if v in timed and f"{v}, {k}" not in timed]
    lines += ["", "Timestamps of compute passes on lavapipe do not bracket the dispatch's work (they read far "
              "below what a CPU can move): there, compare the wall-clock chain times. On a hardware GPU both agree."]
    return "\n".join(lines) + "\n"


def best_shapes(rows: list[PassTime]) -> list[str]:
    """For each knob's sweep: the fastest swept dispatch of each pass, and the chain made of those (the shape per
    pass the plan could choose: core/plan/dispatch.py)."""
    out = []
    for knob in dict.fromkeys(r.intermediate for r in rows if "shape" in r.variant):
        swept = [r for r in rows if "shape" in r.variant and r.intermediate == knob]
        best = [min((r for r in swept if r.effects == e), key=lambda r: r.ms)
                for e in dict.fromkeys(r.effects for r in swept)]
        picks = "; ".join(f"{r.effects} {r.variant.split('shape ')[1]} {r.ms:.3f} ms" for r in best)
        out.append(f"- fastest shape per pass ({knob}): {picks}; that chain {sum(r.ms for r in best):.3f} ms, "
                   f"{chain_ratio(best):.2f}x a copy of the same bytes"
                   + _against_auto(rows, f"compute, fused, {knob}", best))
    return out


def chain_ratio(rows: list[PassTime]) -> float:
    """A chain's time over a copy moving the chain's bytes (issue 31.6: at most 1.3x at 4K)."""
    copy_ms = sum(r.copy_ms for r in rows)
    return sum(r.ms for r in rows) / copy_ms if copy_ms > 0 else float("nan")


def _against_auto(rows: list[PassTime], variant: str, mine: list[PassTime]) -> str:
    """For a set knob post_intermediate: the chain's time over the copy of the "auto" chain's bytes (the same
    image's copy at today's format), so a variant that moves fewer bytes is also judged by time saved."""
    if mine[0].intermediate == "auto":
        return ""
    base_name = variant.removesuffix(f", {mine[0].intermediate}")  # the auto rows' variant: no knob suffix
    base = [r for r in rows if r.variant == base_name]
    copy_ms = sum(r.copy_ms for r in base)
    return f" ({sum(r.ms for r in mine) / copy_ms:.2f}x the copy of the auto chain's bytes)" if copy_ms > 0 else ""


def csv_text(rows: list[PassTime]) -> str:
    fields = [f.name for f in dataclasses.fields(PassTime)] + ["gbps", "copy_gbps", "percent_of_copy"]
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")  # quoted where a field holds a comma ("compute, fused")
    writer.writerow(fields)
    for r in rows:
        values = [getattr(r, f) for f in fields]
        writer.writerow(f"{v:.6g}" if isinstance(v, float) else str(v) for v in values)
    return out.getvalue()


def record_bandwidth(ctx: GPUContext, scene_path: Path, size: tuple[int, int], rows: list[PassTime],
                     command: str) -> Path:
    """Keep each pass's numbers (not the shape sweep's) for ``render --explain`` on this adapter
    (core/files/bandwidth.py)."""
    import datetime

    from wgpurender.core.files import bandwidth

    date = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    records = {bandwidth.pass_key(Path(scene_path).stem, r.effects, r.path): bandwidth.PassRecord(
        r.ms, r.bytes_moved / 1e6, r.copy_ms, f"{size[0]}x{size[1]}", date, command)
        for r in rows if "shape" not in r.variant and r.intermediate == "auto" and r.ms == r.ms}
    return bandwidth.save(ctx.info.get("device", ""), records)
