"""Issue 31.6: final.toml's post chain with FXAA's pass dispatched several ways, interleaved in one process.

The H100's SM clock is not locked, and the compute-bound FXAA pass moved 1.8x between hosts and within runs
(docs/perf-h100/2026-11-27-post2/). So every case here runs in every round, in an order that rotates each round
(and is reversed every other round), a few frames each, GPU timestamps per dispatch; the SM clock is read each
round. A case is judged against main's FXAA pass by the median of per-round ratios (same round, same clock).

Cases: the plan's tonemap pass; the copy kernel moving the chain's bytes (bench post-roofline's roofline); FXAA's
pass as main draws it (its WGSL text given by ``--main-wgsl``, made by main's tree) and as this tree draws it
untiled (must read the same), through the plan's tile, over an edge list
(wgpurender/bench/fxaa_variants/edge_list.py) and with
other shapes; ``part:`` rows time the edge list's first two dispatches alone (no image). After timing, every FXAA
case's image is read back and compared with main's, byte for byte, and the edge list's length is reported.

    python benchmarks/post_interleave.py OUT_DIR [--main-wgsl FILE] [--size 3840x2160] [--rounds 25] [--frames 8]
    python benchmarks/post_interleave.py --by-clock OUT_DIR/interleave.csv   # a run's rows grouped by SM clock
"""

from __future__ import annotations

import argparse
import csv
import statistics
import sys
from pathlib import Path

import numpy as np
import wgpu

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from wgpurender.bench.post_roofline import COPY_WGSL, dispatch_bytes  # noqa: E402
from wgpurender.bench.sm_clock import sm_clock  # noqa: E402
from wgpurender.core.plan import resolve_plan  # noqa: E402
from wgpurender.core.scene import load_scene  # noqa: E402
from wgpurender.wgpu_path.device.context import get_context  # noqa: E402
from wgpurender.wgpu_path.device.targets import read_texture  # noqa: E402
from wgpurender.wgpu_path.device.timing import PassTimer  # noqa: E402
from wgpurender.wgpu_path.post import passes  # noqa: E402

FINAL = ROOT / "assets" / "scenes" / "final.toml"
# (name, shape, tile) of FXAA's pass; None: the plan's
# tile "edges": FXAA's edge search over a list of edge pixels
# (wgpurender/bench/fxaa_variants/edge_list.py), cs_mark's shape given
FXAA_CASES = (("untiled 8x8x2", (8, 8, 2), ""), ("plan", None, None), ("edges 8x8x2", (8, 8, 2), "edges"),
              ("edges 16x8x2", (16, 8, 2), "edges"), ("edges 8x8x4", (8, 8, 4), "edges"),
              ("edges 16x8x4", (16, 8, 4), "edges"), ("edges 32x8x4", (32, 8, 4), "edges"),
              ("untiled 16x8x2", (16, 8, 2), ""), ("untiled 8x8x4", (8, 8, 4), ""),
              ("untiled 16x8x1", (16, 8, 1), ""), ("untiled 32x8x2", (32, 8, 2), ""), ("untiled 8x4x2", (8, 4, 2), ""))
# the edge list's first two dispatches alone (cs_mark, cs_size: every pixel off edges written, the edges listed and
# counted, the count zeroed), no edge search: what the list costs before FXAA's work on the edges; not an image
PART_CASES = (("part: mark+size 16x8x2", (16, 8, 2)), ("part: mark+size 8x8x4", (8, 8, 4)))
# --set gather (post6): FXAA's lumas in the intermediate's alpha
# (wgpurender/bench/fxaa_variants/luma_alpha.py): "tonemap luma"
# writes them (the plan's tonemap with the luma in alpha), the "fxaa gather" cases read them with textureGather;
# their chain is tonemap luma + fxaa gather. Untiled shapes beside them for the same clocks.
GATHER_CASES = (("untiled 8x8x2", (8, 8, 2), ""), ("gather 8x8x2", (8, 8, 2), "gather"),
                ("gather 16x8x2", (16, 8, 2), "gather"), ("gather 8x8x4", (8, 8, 4), "gather"),
                ("gather 16x8x4", (16, 8, 4), "gather"), ("gather 32x8x2", (32, 8, 2), "gather"),
                ("gather 8x8x1", (8, 8, 1), "gather"))
LUMA_TONEMAP = "tonemap luma"


def tonemap_of(name: str, names) -> str:
    """The tonemap case whose image an FXAA case reads: the luma-writing one for a gather case (when timed)."""
    return LUMA_TONEMAP if name.startswith("fxaa gather") and LUMA_TONEMAP in names else "tonemap (plan)"


class CopyCase:
    """bench post-roofline's copy kernel over buffers moving ``n_bytes`` (read + write), made once."""

    def __init__(self, ctx, n_bytes: int) -> None:
        device = ctx.device
        module = device.create_shader_module(label="interleave-copy", code=COPY_WGSL)
        self.pipeline = device.create_compute_pipeline(label="interleave-copy", layout="auto",
                                                       compute={"module": module, "entry_point": "cs_main"})
        half = max(16, n_bytes // 2 // 16 * 16)
        src = device.create_buffer(size=half, usage=wgpu.BufferUsage.STORAGE)
        dst = device.create_buffer(size=half, usage=wgpu.BufferUsage.STORAGE)
        self.group = device.create_bind_group(layout=self.pipeline.get_bind_group_layout(0), entries=[
            {"binding": 0, "resource": {"buffer": src, "offset": 0, "size": half}},
            {"binding": 1, "resource": {"buffer": dst, "offset": 0, "size": half}}])
        groups = -(-(half // 16) // 256)
        self.gx = min(groups, 65535)
        self.gy = -(-groups // self.gx)

    def encode(self, encoder, writes) -> None:
        cp = encoder.begin_compute_pass(timestamp_writes=writes)
        cp.set_pipeline(self.pipeline)
        cp.set_bind_group(0, self.group)
        cp.dispatch_workgroups(self.gx, self.gy, 1)
        cp.end()


class PassCase:
    """One planned pass with a given shape and tile (or a given WGSL text: main's), input and output fixed."""

    def __init__(self, ctx, p, source, target, shape=None, tile=None, text: str | None = None) -> None:
        if tile in ("gather", "luma"):  # reads / writes FXAA's lumas in alpha
            from wgpurender.bench.fxaa_variants.luma_alpha import LumaAlphaPass

            role = "fxaa" if tile == "gather" else "tonemap"
            self.runner, self.source, self.target = LumaAlphaPass(ctx.device, p, role, shape), source, target
            return
        if tile == "edges":
            from wgpurender.bench.fxaa_variants.edge_list import EdgeListPass

            self.runner, self.source, self.target = EdgeListPass(ctx.device, p, shape), source, target
            return
        original = passes.pass_source
        if text is not None:
            passes.pass_source = lambda *a, **k: text
        try:
            self.runner = passes.ComputePass(ctx.device, p, shape, tile)
        finally:
            passes.pass_source = original
        self.source, self.target = source, target

    def encode(self, encoder, writes) -> None:
        self.runner.encode(encoder, self.source, self.target, timestamp_writes=writes)


class MarkCase:
    """An edge-list FXAA pass's cs_mark and cs_size dispatches only (PART_CASES)."""

    def __init__(self, ctx, p, source, target, shape) -> None:
        from wgpurender.bench.fxaa_variants.edge_list import EdgeListPass
        from wgpurender.wgpu_path.post.shaders import dispatch_groups

        self.runner = EdgeListPass(ctx.device, p, shape)
        self.group = self.runner._group(source, target)
        self.groups = dispatch_groups((target.size[0], target.size[1]), shape)

    def encode(self, encoder, writes) -> None:
        cp = encoder.begin_compute_pass(timestamp_writes=writes)
        cp.set_pipeline(self.runner.mark)
        cp.set_bind_group(0, self.group)
        cp.dispatch_workgroups(*self.groups, 1)
        cp.set_pipeline(self.runner.size_pipeline)
        cp.set_bind_group(0, self.runner.size_group)
        cp.dispatch_workgroups(1, 1, 1)
        cp.end()


def time_once(ctx, case, timer: PassTimer) -> float:
    timer.reset()
    encoder = ctx.device.create_command_encoder()
    case.encode(encoder, timer.writes("t"))
    timer.resolve(encoder)
    ctx.queue.submit([encoder.finish()])
    return timer.read().get("t", float("nan"))


def main() -> int:
    if sys.argv[1:2] == ["--by-clock"]:
        with open(sys.argv[2], newline="") as fh:
            rows = [(int(r["round"]), r["case"], int(r["frame"]), float(r["ms"]), r["sm_clock_mhz"])
                    for r in csv.DictReader(fh)]
        print(by_clock(rows), end="")
        return 0
    ap = argparse.ArgumentParser()
    ap.add_argument("out", type=Path)
    ap.add_argument("--main-wgsl", type=Path)
    ap.add_argument("--size", default="3840x2160")
    ap.add_argument("--rounds", type=int, default=25)
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--set", choices=("edges", "gather"), default="edges",
                    help="the FXAA cases: post5's edge list and shapes (default), or post6's lumas in alpha")
    args = ap.parse_args()
    from wgpurender.wgpu_path.scene import SceneRenderer, render_frame

    size = tuple(int(v) for v in args.size.split("x"))
    ctx = get_context()
    scene = load_scene(FINAL)
    plan = resolve_plan(scene, ctx.adapter_facts(), size=size, post_path="compute", post_fuse=True)
    renderer = SceneRenderer(ctx, scene, plan)
    target = renderer.create_output()
    render_frame(ctx, renderer, target)
    if args.set == "gather":  # the lumas in alpha of a second intermediate
        from wgpurender.bench.fxaa_variants.luma_alpha import draw_chain

        middle = draw_chain(ctx, renderer, target)
    textures = {**renderer.attachments, "output": target}
    tonemap, fxaa = plan.post_passes
    # main's text is made without an adapter (--main-wgsl's command): this tree's untiled text must not depend on it
    blind = resolve_plan(scene, None, size=size, post_path="compute", post_fuse=True).post_passes[1]
    args.same_text = passes.pass_source(blind, (8, 8, 2), "") == passes.pass_source(fxaa, (8, 8, 2), "")
    chain_bytes = sum(dispatch_bytes(p, size)[0] for p in plan.post_passes)
    cases = {"copy (chain bytes)": CopyCase(ctx, chain_bytes),
             "tonemap (plan)": PassCase(ctx, tonemap, textures[tonemap.input], textures[tonemap.output])}
    fx_in, fx_out = textures[fxaa.input], textures[fxaa.output]
    if args.main_wgsl:
        cases["fxaa main"] = PassCase(ctx, fxaa, fx_in, fx_out, (8, 8, 2), "", args.main_wgsl.read_text())
    if args.set == "gather":
        cases[LUMA_TONEMAP] = PassCase(ctx, tonemap, textures[tonemap.input], middle, None, "luma")
    for name, shape, tile in (GATHER_CASES if args.set == "gather" else FXAA_CASES):
        cases[f"fxaa {name}"] = PassCase(ctx, fxaa, middle if tile == "gather" else fx_in, fx_out, shape, tile)
    for name, shape in (PART_CASES if args.set == "edges" else ()):
        cases[name] = MarkCase(ctx, fxaa, fx_in, fx_out, shape)
    timer = PassTimer(ctx, max_passes=1)
    names = list(cases)
    for name in names:  # warm-up: pipelines made, caches filled
        for _ in range(3):
            time_once(ctx, cases[name], timer)
    rows = []
    for r in range(args.rounds):
        order = names[r % len(names):] + names[:r % len(names)]
        order = order[::-1] if r % 2 else order
        clock = sm_clock()
        for name in order:
            for f in range(args.frames):
                rows.append((r, name, f, time_once(ctx, cases[name], timer), clock))
    clock_after = sm_clock()
    images = {}
    for name in names:
        if name.startswith("fxaa"):
            encoder = ctx.device.create_command_encoder()
            cases[name].encode(encoder, None)
            ctx.queue.submit([encoder.finish()])
            images[name] = read_texture(ctx, fx_out)
            if hasattr(cases[name].runner, "listed"):
                args.listed = cases[name].runner.listed()
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / "interleave.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["round", "case", "frame", "ms", "sm_clock_mhz"])
        w.writerows(rows)
    text = summary(rows, names, images, ctx, size, chain_bytes, args, clock_after, tonemap, fxaa) + by_clock(rows)
    (args.out / "interleave.md").write_text(text)
    print(text)
    return 0


def _round_medians(rows, name):
    per: dict[int, list[float]] = {}
    for r, n, _, ms, _ in rows:
        if n == name:
            per.setdefault(r, []).append(ms)
    return {r: statistics.median(v) for r, v in per.items()}


def summary(rows, names, images, ctx, size, chain_bytes, args, clock_after, tonemap, fxaa) -> str:
    rounds = {n: _round_medians(rows, n) for n in names}
    clocks = sorted({c for *_, c in rows})
    base = "fxaa main" if "fxaa main" in names else "fxaa untiled 8x8x2"
    ref = images.get(base)
    lines = [f"# final.toml's post chain, FXAA's pass interleaved ({size[0]}x{size[1]})", "",
             f"- adapter: {ctx.describe()}",
             f"- command: `python benchmarks/post_interleave.py OUT {'--main-wgsl FILE ' if args.main_wgsl else ''}"
             f"--size {args.size} --rounds {args.rounds} --frames {args.frames}"
             f"{' --set gather' if args.set == 'gather' else ''}`",
             f"- {args.rounds} rounds, every case {args.frames} dispatches a round (GPU timestamps), the order rotated "
             "each round and reversed every other; SM clock (MHz) read at each round's start: "
             f"{', '.join(clocks)}; after: {clock_after}",
             f"- plan: tonemap {tonemap.shape} tile {tonemap.tile!r}; FXAA {fxaa.shape} tile {fxaa.tile!r}; "
             f"chain bytes {chain_bytes / 1e6:.1f} MB; FXAA's untiled text the same with and without the adapter's "
             f"facts: {args.same_text}",
             f"- edge pixels listed by the edge-list cases: {getattr(args, 'listed', '-')} of {size[0] * size[1]}", "",
             f"| case | median ms | p10 ms | p90 ms | median of per-round ratios to {base} | image = {base}'s |",
             "|---|---:|---:|---:|---:|---|"]
    for n in names:
        allms = sorted(ms for _, m, _, ms, _ in rows if m == n)
        q = statistics.quantiles(allms, n=10)
        ratio = ""
        if n.startswith("fxaa"):
            ratio = f"{statistics.median(rounds[n][r] / rounds[base][r] for r in rounds[n]):.3f}"
        same = "" if n not in images or ref is None else image_verdict(images[n], ref)
        lines.append(f"| {n} | {statistics.median(allms):.4f} | {q[0]:.4f} | {q[-1]:.4f} | {ratio} | {same} |")
    lines += ["", "Chains (tonemap + FXAA case) over the copy of the chain's bytes, the median of per-round ratios "
              "(each round's tonemap, FXAA and copy medians):", ""]
    copy = rounds["copy (chain bytes)"]
    for n in names:
        if n.startswith("fxaa"):
            tm = rounds[tonemap_of(n, names)]
            per = [(tm[r] + rounds[n][r]) / copy[r] for r in rounds[n]]
            ms = statistics.median(tm[r] + rounds[n][r] for r in rounds[n])
            lines.append(f"- {chain_label(n, names)} + {n}: {ms:.4f} ms, {statistics.median(per):.3f}x the copy "
                         f"(rounds {min(per):.3f}-{max(per):.3f}x; copy {statistics.median(copy.values()):.4f} ms)")
    return "\n".join(lines) + "\n"


def chain_label(name: str, names) -> str:
    """The chain's first pass as the summary lines name it: "tonemap" (the plan's) or "tonemap luma"."""
    return "tonemap" if tonemap_of(name, names) == "tonemap (plan)" else LUMA_TONEMAP


def image_verdict(image: np.ndarray, ref: np.ndarray) -> str:
    """"yes" where ``image`` is ``ref`` byte for byte, else how many pixels differ and by how many 8-bit steps at
    most (alpha included)."""
    if np.array_equal(image, ref):
        return "yes"
    diff = np.abs(image.astype(np.int32) - ref.astype(np.int32)).max(-1)
    return f"NO ({int((diff > 0).sum())} px, max {int(diff.max())}, > 1: {int((diff > 1).sum())})"


def by_clock(rows) -> str:
    """Each case's median per SM clock read at the rounds' start (the clock is not locked; it may fall mid-run),
    and the chain tonemap + FXAA case over the copy at each clock."""
    clocks = sorted({c for *_, c in rows}, key=lambda c: -float(c) if c.replace(".", "").isdigit() else 0)
    names = list(dict.fromkeys(n for _, n, *_ in rows))
    med = {(n, c): statistics.median(ms for _, m, _, ms, k in rows if m == n and k == c)
           for n in names for c in clocks if any(m == n and k == c for _, m, _, _, k in rows)}
    lines = ["", "By SM clock (MHz, read at each round's start; rounds at that clock):", "",
             "| case | " + " | ".join(f"{c} ({len({r for r, *_, k in rows if k == c})})" for c in clocks) + " |",
             "|---|" + "---:|" * len(clocks)]
    lines += [f"| {n} | " + " | ".join(f"{med[(n, c)]:.4f}" if (n, c) in med else "" for c in clocks) + " |"
              for n in names]
    copy = "copy (chain bytes)"
    for n in names:
        tm = tonemap_of(n, names)
        if n.startswith("fxaa") and all((x, c) in med for x in (copy, tm, n) for c in clocks):
            lines.append(f"- {chain_label(n, names)} + {n} over the copy: " + ", ".join(
                f"{(med[(tm, c)] + med[(n, c)]) / med[(copy, c)]:.3f}x at {c}" for c in clocks))
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    raise SystemExit(main())
