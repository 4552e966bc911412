"""docs/benchmarks.md's generated figures of issue 31's second H100 run (perf2): the post chain against a copy
of its bytes at 4K (item 6), the final scene's CPU per frame (item 4), Dawn beside wgpu-native (item 8).

Read only from the committed run folder :data:`RUN` (wgpurender/bench/figures.py writes the block; its test
checks the block is current).
"""

from __future__ import annotations

import csv
from pathlib import Path

from wgpurender.bench.report import Result, fmt_ms, markdown_table, read_csv

RUN = "perf-h100/2026-11-27-issue31-perf2"
CHAIN_LIMIT = 1.3  # item 6: the fused chain at most 1.3x a copy of the same bytes
CPU_LIMIT_MS = 0.3  # item 4: CPU per frame of the final scene
ROOFLINE_SCENES = ("final", "final_subpass")
FUSED = "compute, fused"
NUMBERS = ("bytes_moved", "ms", "copy_ms", "copy_bytes", "chain_wall_ms", "gbps", "copy_gbps", "percent_of_copy")


def roofline_rows(path: Path) -> list[dict]:
    """post_roofline.csv_text's rows; the variant ("compute, fused") holds a comma, unquoted in files written
    before csv_text quoted it (the committed runs): the numeric fields are taken from the right, the text ones
    from the left, which reads both."""
    with path.open(newline="") as f:
        header, *rows = list(csv.reader(f))
    # the knob post_intermediate's column (runs from 2026-11-27's post branch on), counted from the right
    knob = len(header) - header.index("intermediate") if "intermediate" in header else None
    out = []
    for row in rows:
        intermediate = row.pop(len(row) - knob) if knob else "auto"
        numbers, text = row[-len(NUMBERS):], row[:-len(NUMBERS)]
        out.append({"variant": ",".join(text[:-2]), "effects": text[-2], "path": text[-1],
                    "intermediate": intermediate, **{k: float(v) for k, v in zip(NUMBERS, numbers, strict=True)}})
    return out


def chain_ratio(rows: list[dict]) -> tuple[float, float, int]:
    """(the fused compute chain's ms, a copy of the same bytes' ms, passes): the sums over its passes."""
    mine = [r for r in rows if r["variant"] == FUSED]
    return sum(r["ms"] for r in mine), sum(r["copy_ms"] for r in mine), len(mine)


def _chain_table(base: Path, judge) -> str:
    out = []
    for scene in ROOFLINE_SCENES:
        rows = roofline_rows(base / "roofline" / f"post-roofline-{scene}.csv")
        ms, copy, n = chain_ratio(rows)
        passes = " + ".join(f"{r['effects']} {fmt_ms(r['ms'])}" for r in rows if r["variant"] == FUSED)
        out.append((scene, f"{n}: {passes}", fmt_ms(ms), fmt_ms(copy), f"{ms / copy:.2f}x",
                    judge(ms <= CHAIN_LIMIT * copy)))
    return markdown_table(("scene", "passes (ms)", "chain ms", "copy ms", "chain / copy", f"<= {CHAIN_LIMIT}x"),
                          out)


def cpu_table(rows: list[Result], judge) -> str:
    out = [(r.size, fmt_ms(r.median), fmt_ms(r.p99), judge(r.median <= CPU_LIMIT_MS)) for r in rows
           if (r.family, r.case, r.path, r.metric) == ("scene", "final", "wgpu", "cpu_ms:untimed")]
    return markdown_table(("size", "CPU ms per frame (median)", "p99", f"<= {CPU_LIMIT_MS} ms"), out)


def section(repo: Path, judge, dawn_table) -> list[str]:
    """The block's lines for the perf2 run."""
    base = repo / "docs" / RUN
    link = f"[`docs/{RUN}/`]({RUN}/)"
    not_offered = sorted({f"{r.case} {r.size}" for r in read_csv(base / "dawn/results.csv")
                          if r.metric == "not offered"})
    return ["#### NVIDIA H100, second run (H100 has few graphics units; fragment passes are raster-bound)", "",
            f"From {link} (machine.txt, commands.txt; `benchmarks/issue31_perf2_device_run.sh`).", "",
            "Fused compute post chain at 3840x2160 against a same-run copy of its bytes (GPU timestamps):", "",
            _chain_table(base, judge), "",
            "The final scene's CPU per frame (record + submit without timestamps, as a window draws it):", "",
            cpu_table(read_csv(base / "scene/results.csv"), judge), "",
            "The Dawn binding beside wgpu-native, same call, same flags (`--only frames,scene --no-raw --no-big`); "
            f"not offered by Dawn (one CSV row each): {', '.join(not_offered) or 'none'}:", "",
            dawn_table(read_csv(base / "native/results.csv"), read_csv(base / "dawn/results.csv")), ""]
