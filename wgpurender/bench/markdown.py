"""The markdown report of one perf run: machine, command, targets, then one section per family."""

from __future__ import annotations

from wgpurender.bench import markdown_scale
from wgpurender.bench.report import Result, comparison_table, fmt_ms, markdown_table, results_table, spread

# Numbers given for the C++ tutorial program (we cannot build it here): ms per frame at 800x600, 2 cores.
CPP_GIVEN_MS = {"chapter 28": 47.0, "chapter 30": 75.0}


def _pick(results: list[Result], family: str, metric: str | None = None, path: str | None = None) -> list[Result]:
    return [r for r in results if r.family == family and (metric is None or r.metric == metric)
            and (path is None or r.path == path)]


def _one(results: list[Result], family: str, case: str, path: str, size: str, metric: str) -> Result | None:
    for r in results:
        if (r.family, r.case, r.path, r.size, r.metric) == (family, case, path, size, metric):
            return r
    return None


def _verdict(run, met: bool, applies: str = "") -> str:
    """'met'/'not met', unless the run cannot judge: --quick (tiny sizes, few frames) or ``applies`` says why not."""
    if run.config.quick:
        return "not judged (--quick: harness check)"
    if applies:
        return f"not judged ({applies})"
    return "met" if met else "not met"


def _on_cpu(run) -> bool:
    return "CPU" in run.machine.get("adapter", "")


def _targets(run) -> str:
    res = run.results
    rows = []
    limit = 1.05  # issue 22: every stage within 1.05x of raw on a GPU too (issue 7 had 1.10 there)
    for case in sorted({r.case for r in _pick(res, "scene", "frame_ms", "raw")}):
        wg = {r.size: r for r in _pick(res, "scene", "frame_ms", "wgpu") if r.case == case}
        rw = {r.size: r for r in _pick(res, "scene", "frame_ms", "raw") if r.case == case}
        both = [s for s in wg if s in rw and rw[s].median > 0]
        if both:
            size, worst = max(((s, wg[s].median / rw[s].median) for s in both), key=lambda x: x[1])
            rows.append((f"final scene ({case}.toml) wgpu / raw frame time <= {limit:.2f}",
                         f"worst {size} {worst:.2f}x", _verdict(run, worst <= limit)))
    ratios = [(r.case, r.size, r.median / p.median) for r in _pick(res, "frames", "frame_ms", "wgpu")
              for p in [_one(res, "frames", r.case, "raw", r.size, "frame_ms")] if p and p.median > 0]
    if ratios:
        case, size, worst = max(ratios, key=lambda x: x[2])
        within = sum(1 for *_, q in ratios if q <= limit)
        rows.append((f"wgpu / raw frame time <= {limit:.2f}, stage by stage",
                     f"{within}/{len(ratios)} stage-sizes within {limit:.2f}x; worst {case} {size} {worst:.2f}x",
                     _verdict(run, within == len(ratios))))
    for chapter, ms in CPP_GIVEN_MS.items():
        case = f"vulkan_tutorial_{chapter.split()[-1]}"
        ours = [r for r in _pick(res, "scene", "frame_ms", "wgpu") if r.case == case]
        if ours:
            q = ours[0].median / ms
            rows.append((f"tutorial {chapter} ({ms:g} ms given, C++ not built here) within 1.05x",
                         f"{case} {ours[0].size}: {fmt_ms(ours[0].median)} ms = {q:.2f}x of the given number",
                         _verdict(run, q <= 1.05, "" if _on_cpu(run) else
                                  "the given C++ numbers were taken on lavapipe, this adapter is not")))
        else:
            rows.append((f"tutorial {chapter} ({ms:g} ms given, C++ not built here) within 1.05x",
                         "tutorial scene not measured", "n/a"))
    cpu = [r for r in _pick(res, "scene", "cpu_ms", "wgpu") if r.case in ("final", "final_subpass")]
    proxy = ""
    if not cpu:
        cpu = _pick(res, "frames", "cpu_ms", "wgpu")
        cpu = [r for r in cpu if r.case == "3d"]
        proxy = " (stage 3d as proxy)"
    untimed = [r for r in _pick(res, "scene", "cpu_ms:untimed", "wgpu") if r.case in ("final", "final_subpass")]
    calls = [r for r in _pick(res, "scene", "native_calls", "wgpu") if r.case == "final"]
    if untimed:
        worst = max(untimed, key=lambda r: r.median)
        timed = max(r.median for r in cpu) if cpu else float("nan")
        per = f"; {calls[0].median:.0f} native calls per frame" if calls else ""
        rows.append(("CPU encode + submit <= 0.3 ms per frame (final scene, as a window draws it)",
                     f"{fmt_ms(worst.median)} ms ({worst.case} {worst.size}, worst){per}; with pass timestamps "
                     f"{fmt_ms(timed)} ms", _verdict(run, worst.median <= 0.3)))
    elif cpu:
        worst = max(r.median for r in cpu)
        rows.append((f"CPU encode + submit <= 0.3 ms per frame{proxy}", f"{fmt_ms(worst)} ms (worst size)",
                     _verdict(run, worst <= 0.3)))
    objects = [r for r in _pick(res, "objects", "frame_ms") if r.case.endswith("/10000")]
    if objects:
        best = min(objects, key=lambda r: r.median)
        fps = 1000.0 / best.median
        rows.append(("10k objects at >= 60 fps", f"{fps:.0f} fps ({best.case.split('/')[0]})",
                     _verdict(run, fps >= 60, "the target is for a GPU" if _on_cpu(run) else "")))
    million = [r for mode in ("gpu-animated", "gpu-compute-raster")
               for r in [_one(res, "objects", f"{mode}/1000000", "wgpu", "800x600", "frame_ms")] if r]
    if million:
        best = min(million, key=lambda r: r.median)
        mode = best.case.split("/")[0]
        fps = 1000.0 / best.median
        cpu = [r.median for r in _pick(res, "objects", "cpu_ms:untimed") if r.case.startswith(f"{mode}/")]
        timed = [r.median for r in _pick(res, "objects", "cpu_ms") if r.case.startswith(f"{mode}/")]
        worst_cpu = max(cpu or timed) if (cpu or timed) else float("nan")
        how = "as an application draws it" if cpu else "with timestamp queries"
        rows.append(("1M animated objects at >= 60 fps, CPU <= 0.3 ms per frame at every count",
                     f"{fps:.0f} fps ({mode}); CPU worst {fmt_ms(worst_cpu)} ms over its counts ({how}; with "
                     f"timestamp queries {fmt_ms(max(timed)) if timed else '-'} ms)",
                     _verdict(run, fps >= 60 and worst_cpu <= 0.3, "the target is for a GPU" if _on_cpu(run) else "")))
    inc = [q for _, w, r in _post_increments(res) if r > 0 for q in [w / r]]  # a raw increment <= 0: noise
    if inc:
        worst = max(inc)
        rows.append(("post pass no more expensive than the raw subpass (GPU ms, msaa-post minus msaa)",
                     f"worst wgpu/raw {worst:.2f}x", _verdict(run, worst <= 1.0)))
    rows += markdown_scale.targets(res, lambda met, applies="": _verdict(run, met, applies))
    return markdown_table(("target", "measured", "status"), rows)


def _post_increments(res: list[Result]) -> list[tuple[str, float, float]]:
    """(size, wgpu post ms, raw post ms): msaa-post minus msaa alone, GPU time, per path."""
    out = []
    for r in _pick(res, "msaa-post", "gpu_ms", "wgpu"):
        if r.case != "msaa-post":
            continue
        w0 = _one(res, "msaa-post", "msaa alone", "wgpu", r.size, "gpu_ms")
        r1 = _one(res, "msaa-post", "msaa-post", "raw", r.size, "gpu_ms")
        r0 = _one(res, "msaa-post", "msaa alone", "raw", r.size, "gpu_ms")
        if w0 and r1 and r0:
            out.append((r.size, r.median - w0.median, r1.median - r0.median))
    return out


def _objects_table(res: list[Result]) -> str:
    rows = []
    for r in _pick(res, "objects", "frame_ms"):
        cpu = _one(res, "objects", r.case, r.path, r.size, "cpu_ms")
        gpu = _one(res, "objects", r.case, r.path, r.size, "gpu_ms")
        setup = _one(res, "objects", r.case, r.path, r.size, "setup_ms")
        mode, count = r.case.split("/")
        rows.append((mode, count, spread(r), spread(cpu) if cpu else "-", spread(gpu) if gpu else "-",
                     f"{1000.0 / r.median:.0f}", fmt_ms(setup.median) if setup else "-"))
    return markdown_table(("mode", "objects", "frame ms", "CPU ms", "GPU ms", "fps", "set-up ms"), rows)


def _startup_table(res: list[Result]) -> str:
    """Each configuration's phase medians; its paired wgpu/raw ratio (bench/startup.py) in the last column."""
    from wgpurender.bench.startup import METRICS, RATIO

    columns = (*METRICS, "make_ms")
    cases: dict[tuple[str, str], dict[str, Result]] = {}
    for r in _pick(res, "startup"):
        cases.setdefault((r.case, r.path), {})[r.metric] = r
    paired = {case: m[RATIO] for (case, path), m in cases.items() if RATIO in m}
    rows = [(case, path, *(fmt_ms(m[p].median) if p in m else "-" for p in columns),
             f"{paired[case].median:.2f}x [{paired[case].p10:.2f}..{paired[case].p90:.2f}]"
             if path == "wgpu" and case in paired else "-")
            for (case, path), m in cases.items() if RATIO not in m]
    return markdown_table(("case", "path", *(p.removesuffix("_ms") + " ms" for p in columns),
                           "x raw, paired [p10..p90]"), rows)


def _tails(res: list[Result]) -> str:
    """Every timed case whose p90 is over TAIL_FACTOR x its median, with its p99; or a line saying none."""
    from wgpurender.bench.report import TAIL_FACTOR

    timed = [r for r in res if r.metric.endswith("_ms") and r.n >= 5]
    tails = [r for r in timed if r.has_tail()]
    head = (f"{len(tails)} of {len(timed)} timed rows have p90 > {TAIL_FACTOR:g}x their median "
            "(rows of at least 5 samples).")
    if not tails:
        return head
    rows = [(r.family, r.case, r.path, r.size or "-", r.metric, spread(r), f"{r.p90 / r.median:.1f}x") for r in tails]
    return head + "\n\n" + markdown_table(("family", "case", "path", "size", "metric", "p50 [p10..p90] p99",
                                            "p90/p50"), rows)


def render_markdown(run, plots: dict[str, str]) -> str:
    res = run.results
    lines = ["# wgpurender performance run", ""]
    lines += [f"- **{k}**: {v}" for k, v in run.machine.items()]
    lines += [f"- **command**: `{run.config.command or 'run_perf()'}`",
              f"- **mode**: {'quick (harness check; numbers not meaningful)' if run.config.quick else 'full'}, "
              f"{run.config.timed_frames()} timed frames per case; duration {run.seconds:.0f} s",
              "", "All times in ms: p50 [p10..p90] p99 over the timed frames. Compare ratios within this run.", ""]
    lines += ["## Targets", "", _targets(run), ""]
    lines += ["## Tails (stalls a median hides)", "", _tails(res), ""]
    if _pick(res, "frames"):
        lines += ["## Frame time: wgpu vs raw Vulkan, same stage", "",
                  "frame = record + submit + wait; cpu = record + submit; gpu = timestamps around the stage's "
                  "passes; readback = frame with readback minus frame.", ""]
        for metric in ("frame_ms", "gpu_ms", "cpu_ms", "readback_ms"):
            lines += [f"### {metric}", "", comparison_table(_pick(res, "frames"), metric=metric), ""]
    if _pick(res, "scene"):
        lines += ["## Final scene", "", results_table(_pick(res, "scene")), ""]
    if _pick(res, "post-effects"):
        lines += ["## Post effects (one pass each)", "",
                  results_table([r for r in _pick(res, "post-effects") if r.metric in ("gpu_ms", "cpu_ms")]), ""]
    if _pick(res, "post-probe"):
        lines += ["## Post pass taken apart (a full-screen copy, one knob changed per row; GPU ms)", "",
                  results_table(_pick(res, "post-probe", "gpu_ms")), ""]
    if _pick(res, "msaa-post"):
        timed = [r for r in _pick(res, "msaa-post") if r.metric != "declared_mb"]
        lines += ["## MSAA + one post effect: wgpu (two passes) vs raw (two subpasses)", "",
                  comparison_table(timed), ""]
        traffic = {(r.size, r.path): r.median for r in _pick(res, "msaa-post", "declared_mb")}
        sizes = list(dict.fromkeys(size for size, _ in traffic))
        if sizes:
            lines += ["Memory traffic the load/store ops declare per frame (MB; bench/post.py msaa_post_traffic: "
                      "a tiler's saving, not lavapipe's or a desktop GPU's):", "",
                      markdown_table(("size", "wgpu (two passes)", "raw (two subpasses)", "extra"),
                                     [(s, f"{traffic[(s, 'wgpu')]:.2f}", f"{traffic[(s, 'raw')]:.2f}",
                                       f"{traffic[(s, 'wgpu')] - traffic[(s, 'raw')]:.2f}") for s in sizes]), ""]
        inc = _post_increments(res)
        if inc:
            lines += ["Post increment (msaa-post minus msaa alone, GPU ms):", "",
                      markdown_table(("size", "wgpu post", "raw subpass", "wgpu/raw"),
                                     [(s, fmt_ms(w), fmt_ms(r), f"{w / r:.2f}x" if r > 0 else "-")
                                      for s, w, r in inc]), ""]
    if _pick(res, "objects"):
        lines += ["## Many objects (800x600, quads of ~4 px)", "", _objects_table(res), ""]
    if _pick(res, "scene-scale"):
        lines += ["## Scene scale: N copies of a lit, textured cube (instanced: one instances block; batched: N models "
                  "of one file), N distinct meshes, pygfx beside", "", markdown_scale.table(res), ""]
    if _pick(res, markdown_scale.CONTROL):
        lines += ["## Control: the host's own tail (no renderer; sampled as the frame rows)", "",
                  results_table(_pick(res, markdown_scale.CONTROL)), ""]
    if _pick(res, "startup"):
        lines += ["## First frame (fresh process per run)", "", _startup_table(res), ""]
    if plots:
        lines += ["## Plots", ""] + [f"![{k}]({name})" for k, name in plots.items()] + [""]
    if run.notes:
        lines += ["## Notes", ""] + [f"- {n}" for n in run.notes] + [""]
    return "\n".join(lines)
