"""The perf report's pygfx target (issue 31): 10k instances at most 0.5x pygfx ``InstancedMesh``'s frame time.

Judged on the paired row (bench/scale_paired.py: the median of per-round ratios, both sides alive together, the
order flipped each round), shown with its p10/p90, each side's median and the SM clock's range over the rounds. The
sequential row (two medians measured one after the other) is reported beside it: on the H100 the clock can move
between the two cases, so it is not judged. A run from before the paired rounds has the sequential row alone:
shown, not judged (as the first pixel's medians in markdown_scale.first_pixel_ratio).
"""

from __future__ import annotations

from wgpurender.bench.report import Result, fmt_ms

GOAL = 0.5
COUNT = 10_000
TITLE = "10k instances <= 0.5x pygfx InstancedMesh frame time"


def _find(res: list[Result], case: str, path: str, metric: str) -> Result | None:
    return next((r for r in res if r.family == "scene-scale" and (r.case, r.path, r.metric) == (case, path, metric)),
                None)


def clock_text(row: Result | None) -> str:
    """The SM clock's range over the rounds (``"SM clock 1080-1980 MHz"``), or what the row says instead."""
    if row is None:
        return "SM clock not recorded"
    if row.n == 0:
        return row.note
    lo, hi = round(row.p10), round(row.p90)
    return f"SM clock {lo} MHz" if lo == hi else f"SM clock {lo}-{hi} MHz"


def pygfx_targets(res: list[Result], verdict) -> list[tuple[str, str, str]]:
    """(target, measured, status) rows; ``verdict(met, applies="")`` is the report's judge."""
    ratio = f"ratio/{COUNT}"
    paired, seq = _find(res, ratio, "wgpu/pygfx", "frame_ratio:paired"), _find(res, ratio, "wgpu/pygfx", "frame_ratio")
    out = []
    if paired is not None:
        mine = _find(res, f"instanced/{COUNT}", "wgpu", "frame_readback_ms:paired")
        theirs = _find(res, f"pygfx/{COUNT}", "pygfx", "frame_readback_ms:paired")
        medians = (f"; medians {fmt_ms(mine.median)} / {fmt_ms(theirs.median)} ms"
                   if mine is not None and theirs is not None else "")
        out.append((TITLE, f"{paired.median:.2f}x, paired over {paired.n} interleaved rounds [p10 {paired.p10:.2f}"
                    f"..p90 {paired.p90:.2f}]{medians}; {clock_text(_find(res, ratio, 'wgpu/pygfx', 'sm_clock_mhz'))}",
                    verdict(paired.median <= GOAL)))
    if seq is not None:
        measured = f"{seq.median:.2f}x (frame with readback, medians measured one after the other, same run)"
        if paired is None:
            out.append((TITLE, measured, verdict(seq.median <= GOAL, applies="no paired rounds in this run")))
        else:
            out.append(("10k instances vs pygfx, sequential medians", measured, "reported"))
    return out
