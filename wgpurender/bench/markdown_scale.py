"""The scene-scale family's part of the perf report (issue 31): its targets and its table.

Targets, each judged from the run's rows (never from a number written here):

- 10k instances at most 0.5x pygfx ``InstancedMesh``'s frame time (both timed with the readback), judged on the
  paired rounds (bench/markdown_pygfx.py);
- a 10k-object scene loads in at most 1 s (the instanced one; the batched one, N models of one mesh file, and the
  distinct one where they were measured);
- CPU per frame does not grow with the instance count: the largest count's CPU median at most
  :data:`CPU_GROWTH` x the smallest's, judged on the same-wait row where the run has it (:func:`_growth`);
- the first pixel at most 1.2x raw's with Python bytecode cached (and the ratio without, reported): the median of
  the startup family's paired per-round ratios;
- frame rows' p99 at most 2x their median (``frame_ms`` and ``cpu_ms`` of the frames, scene and scene-scale
  families: the tail check covers the CPU metric too); beside it the control family's rows (bench/control.py: the
  same sampling with no renderer), over or within the same 2x, so a reader can tell the host's tail from ours.
"""

from __future__ import annotations

from wgpurender.bench.markdown_pygfx import pygfx_targets
from wgpurender.bench.report import Result, fmt_ms, markdown_table

CPU_GROWTH = 1.5  # "does not grow": the noise of a sub-millisecond median between two cases, not a trend
P99_FACTOR = 2.0
SAME_WAIT = "cpu_ms:same_wait"  # the metric of bench/scale.py's same_wait_cpu rows
TAIL_FAMILIES = ("frames", "scene", "scene-scale")
CONTROL = "control"  # bench/control.py's family: sampled as TAIL_FAMILIES' frames, but no renderer in it
LOAD_KINDS = (("instanced", "instanced"), ("batched", "batched: N models of one file"), ("distinct", "distinct"))


def _rows(res: list[Result], metric: str, path: str = "wgpu") -> dict[str, Result]:
    return {r.case: r for r in res if r.family == "scene-scale" and r.metric == metric and r.path == path}


def _count(case: str) -> int:
    return int(case.split("/")[1])


def targets(res: list[Result], verdict) -> list[tuple[str, str, str]]:
    """(target, measured, status) rows; ``verdict(met, applies="")`` is the report's judge."""
    out = pygfx_targets(res, verdict)
    loads = _rows(res, "load_ms")
    for kind, words in LOAD_KINDS:
        r = loads.get(f"{kind}/10000")
        if r is not None:
            out.append((f"a 10k-object scene loads in <= 1 s ({words})", f"{r.median / 1e3:.2f} s",
                        verdict(r.median <= 1000.0)))
    out += _growth(res, verdict)
    for label, judged in (("no caches", True), ("no caches, no bytecode", False)):
        row = first_pixel_ratio(res, label, verdict, judged)
        if row:
            out.append(row)
    frames = [r for r in res if r.family in TAIL_FAMILIES and r.metric in ("frame_ms", "cpu_ms") and r.n >= 5
              and r.p99 == r.p99 and r.median > 0]
    if frames:
        over = [r for r in frames if r.p99 > P99_FACTOR * r.median]
        worst = max(frames, key=lambda r: r.p99 / r.median)
        out.append(("p99 <= 2x median in the frame rows (frame and CPU)",
                    f"{len(over)} of {len(frames)} rows over; worst {worst.p99 / worst.median:.1f}x "
                    f"({worst.family} {worst.case} {worst.path} {worst.size} {worst.metric})", verdict(not over)))
    control = control_row(res)
    if control:
        out.append(control)
    return out


def control_row(res: list[Result]) -> tuple[str, str, str] | None:
    """The control family's rows (no renderer, sampled as the frame rows): each one's median, p99 and p99/median,
    and whether any is over :data:`P99_FACTOR`: then the host alone makes such tails. None without control rows."""
    rows = [r for r in res if r.family == CONTROL and r.metric in ("frame_ms", "cpu_ms") and r.n >= 5
            and r.p99 == r.p99 and r.median > 0]
    if not rows:
        return None
    over = [r for r in rows if r.p99 > P99_FACTOR * r.median]
    parts = [f"{r.case} {r.metric.removesuffix('_ms')} {fmt_ms(r.median)} ms, p99 {fmt_ms(r.p99)} ms "
             f"({r.p99 / r.median:.2f}x)" for r in rows]
    return ("control: p99 <= 2x median with no renderer (sampled as the frame rows)",
            f"{len(over)} of {len(rows)} rows over: " + "; ".join(parts),
            "over: the host alone makes such tails" if over else "within: no host tail in this run")


def _growth(res: list[Result], verdict) -> list[tuple[str, str, str]]:
    """CPU per frame against the instance count. Judged: the same-wait row where the run has it at two counts or
    more (every count's record after the same time off the CPU: the count is the only variable); then ``cpu_ms``
    (each frame after its own GPU wait, as a window without vsync draws it) is reported beside it. A run without
    that row (before issue 31's frametime pass) judges ``cpu_ms``, as it did."""
    rows = {m: {_count(c): r for c, r in _rows(res, m).items() if c.startswith("instanced/")}
            for m in (SAME_WAIT, "cpu_ms", "cpu_thread_ms")}
    judged = SAME_WAIT if _spans(rows[SAME_WAIT], rows["cpu_ms"]) else "cpu_ms"
    out = []
    for metric, label in ((SAME_WAIT, "CPU per frame does not grow with the instance count (same wait before "
                                      "every frame: the count is the only variable)" if judged == SAME_WAIT
                           else "CPU per frame vs the instance count, same wait before every frame (not at every "
                           "count: a frame longer than the period has none)"),
                          ("cpu_ms", "CPU per frame does not grow with the instance count" if judged == "cpu_ms"
                           else "CPU per frame vs the instance count, each frame after its own GPU wait"),
                          ("cpu_thread_ms", "CPU per frame, thread CPU time (no waits), vs the instance count")):
        cpu = rows[metric]
        if len(cpu) >= 2:
            lo, hi = cpu[min(cpu)], cpu[max(cpu)]
            growth = hi.median / lo.median
            out.append((label, f"{fmt_ms(lo.median)} ms at {min(cpu)}, {fmt_ms(hi.median)} ms at {max(cpu)} "
                        f"({growth:.2f}x)", verdict(growth <= CPU_GROWTH) if metric == judged else "reported"))
    return out


def _spans(same: dict[int, Result], cpu: dict[int, Result]) -> bool:
    """Whether the same-wait row covers the counts ``cpu_ms`` does, the smallest and the largest: a count whose
    frame is longer than the period has no same-wait row, and a verdict over the counts left would judge a
    narrower range than the target names."""
    return len(same) >= 2 and (not cpu or (min(same), max(same)) == (min(cpu), max(cpu)))


def first_pixel_ratio(res: list[Result], label: str, verdict, judged: bool) -> tuple[str, str, str] | None:
    """The first pixel's target row from the startup family's paired ratios (wgpu / raw of the same round:
    bench/startup.py), their spread over the rounds and the ratio of the two medians beside them."""
    rows = {r.path: r for r in res if r.family == "startup" and r.case.split(": ", 1)[-1] == label
            and r.metric in ("total_ms", "ratio_total")}
    paired, wgpu, raw = rows.get("wgpu/raw"), rows.get("wgpu"), rows.get("raw")
    if wgpu is None or raw is None or raw.median <= 0:
        return None
    what = "bytecode cached" if judged else "no bytecode (every module compiled)"
    title = f"first pixel <= 1.2x raw ({what})" if judged else f"first pixel vs raw ({what})"
    medians = f"{fmt_ms(wgpu.median)} / {fmt_ms(raw.median)} ms"
    if paired is None:  # a run from before the paired rounds (2026-11-27 evening): its medians, not judged
        q = wgpu.median / raw.median
        return (title, f"{medians} = {q:.2f}x (medians of back-to-back runs)",
                verdict(q <= 1.2, applies="no paired rounds in this run") if judged else "reported")
    measured = (f"{paired.median:.2f}x, paired over {paired.n} interleaved rounds [p10 {paired.p10:.2f}..p90 "
                f"{paired.p90:.2f}]; medians {medians}")
    return title, measured, verdict(paired.median <= 1.2) if judged else "reported"


def table(res: list[Result]) -> str:
    """One row per case: frame, CPU, frame with readback, load, memory."""
    rows = []
    for path in ("wgpu", "pygfx"):
        frame, cpu, rb = _rows(res, "frame_ms", path), _rows(res, "cpu_ms", path), _rows(res, "frame_readback_ms", path)
        load, mem = _rows(res, "load_ms", path), _rows(res, "memory_mb", path)
        for case in sorted(set(cpu) | set(rb), key=lambda c: (c.split("/")[0], _count(c))):
            def ms(d: dict, case: str = case) -> str:
                return fmt_ms(d[case].median) if case in d else "-"

            note = frame[case].note if case in frame else (rb[case].note if case in rb else "")
            rows.append((case, path, ms(frame), ms(cpu), ms(rb), ms(load),
                         f"{mem[case].median:.0f}" if case in mem else "-", note))
    return markdown_table(("case", "path", "frame ms", "CPU ms", "frame + readback ms", "load ms", "memory MB",
                           "note"), rows)
