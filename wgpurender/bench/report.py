"""Benchmark results as rows, and the files they become: CSV, a markdown report and (optional) PNG plots.

A :class:`Result` is one measured quantity: a median with its 10th/90th percentile
spread over ``n`` samples, in the unit of its metric (milliseconds unless the
metric says otherwise). Ratios are always taken between rows of the same run.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, fields
from pathlib import Path

from wgpurender.wgpu_path.device.timing import Stats

CSV_COLUMNS = ("family", "case", "path", "size", "metric", "median", "p10", "p90", "n", "note", "p99")
TAIL_FACTOR = 3.0  # a case whose p90 exceeds this many medians has stalls, whatever its median says


@dataclass(frozen=True)
class Result:
    family: str  # frames, objects, post, post-probe, startup ...
    case: str  # stage, scene, effect, mode/count ...
    path: str  # wgpu, raw, cpp (given numbers) ...
    size: str  # "800x600", or "" where size does not apply
    metric: str  # frame_ms, cpu_ms, gpu_ms, readback_ms, first_frame_ms ...
    median: float
    p10: float
    p90: float
    n: int
    note: str = ""
    p99: float = float("nan")  # nan where the row is not a sample distribution (given numbers, one-off values)

    @classmethod
    def of(cls, family: str, case: str, path: str, size: str, metric: str, stats: Stats, note: str = "") -> Result:
        return cls(family, case, path, size, metric, stats.median, stats.p10, stats.p90, stats.n, note, stats.p99)

    def has_tail(self) -> bool:
        """p90 over TAIL_FACTOR x the median: a time distribution with stalls in it (issue 22)."""
        return self.metric.endswith("_ms") and self.n >= 5 and self.median > 0 and self.p90 > TAIL_FACTOR * self.median

    def key(self) -> tuple[str, str, str, str]:
        """What a peer must share to be compared: everything but the path."""
        return self.family, self.case, self.size, self.metric


NOT_OFFERED = "not offered"  # the metric of a row whose case this binding cannot run (its note says why)


def not_offered(family: str, case: str, size: str, why: str) -> Result:
    """A row saying the wgpu path on this binding cannot run ``case`` (e.g. Dawn has no clear-texture)."""
    nan = float("nan")
    return Result(family, case, "wgpu", size, NOT_OFFERED, nan, nan, nan, 0, why)


def command_line() -> str:
    """The command that is running, as a person would type it (for reports); a bench run from another program
    (pytest, a script) says which, never labelling that program's arguments as a wgpurender command."""
    import shlex
    import sys
    from pathlib import Path

    program = Path(sys.argv[0])
    if program.name == "wgpurender" or (program.name == "__main__.py" and program.parent.name == "wgpurender"):
        return "wgpurender " + " ".join(shlex.quote(a) for a in sys.argv[1:])
    return f"run from {program.name or 'python'}, not a wgpurender command"


def size_text(size: tuple[int, int]) -> str:
    return f"{size[0]}x{size[1]}"


def ratios(results: Sequence[Result], numerator: str, denominator: str) -> dict[tuple, float]:
    """median(numerator path) / median(denominator path) for every key both paths measured."""
    by_key: dict[tuple, dict[str, Result]] = {}
    for r in results:
        by_key.setdefault(r.key(), {})[r.path] = r
    out = {}
    for key, paths in by_key.items():
        if numerator in paths and denominator in paths and paths[denominator].median > 0:
            out[key] = paths[numerator].median / paths[denominator].median
    return out


# -- CSV ---------------------------------------------------------------------------------------


def write_csv(results: Iterable[Result], path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        for r in results:
            row = asdict(r)
            for name in ("median", "p10", "p90", "p99"):
                row[name] = f"{row[name]:.4f}"
            writer.writerow(row)
    return path


def read_csv(path: Path) -> list[Result]:
    types = {f.name: f.type for f in fields(Result)}
    out = []
    with Path(path).open(newline="") as f:
        for row in csv.DictReader(f):
            values = {k: (float(v or "nan") if types[k] == "float" else int(v) if types[k] == "int" else v)
                      for k, v in row.items() if k in types}
            out.append(Result(**values))
    return out


# -- markdown ----------------------------------------------------------------------------------


def fmt_ms(value: float) -> str:
    if math.isnan(value):
        return "-"
    return f"{value:.3f}" if value < 10 else f"{value:.1f}" if value < 1000 else f"{value:.0f}"


def spread(r: Result) -> str:
    """p50 [p10..p90], and p99 where the row has one: the tail a median hides."""
    tail = "" if math.isnan(r.p99) else f" p99 {fmt_ms(r.p99)}"
    return f"{fmt_ms(r.median)} [{fmt_ms(r.p10)}..{fmt_ms(r.p90)}]{tail}"


def markdown_table(header: Sequence[str], rows: Iterable[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(" --- " for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def results_table(results: Sequence[Result]) -> str:
    """Every row: case, path, size, metric, median [p10..p90], n, note."""
    rows = [(r.case, r.path, r.size or "-", r.metric, spread(r), r.n, r.note) for r in results]
    return markdown_table(("case", "path", "size", "metric", "p50 [p10..p90] p99", "n", "note"), rows)


def comparison_table(results: Sequence[Result], numerator: str = "wgpu", denominator: str = "raw",
                     metric: str | None = None) -> str:
    """One line per key measured on both paths: both medians (with spread) and their ratio."""
    by_key: dict[tuple, dict[str, Result]] = {}
    for r in results:
        if metric is None or r.metric == metric:
            by_key.setdefault(r.key(), {})[r.path] = r
    rows = []
    for (_, case, size, m), paths in by_key.items():
        if numerator in paths and denominator in paths:
            a, b = paths[numerator], paths[denominator]
            ratio = f"{a.median / b.median:.2f}x" if b.median > 0 else "-"
            rows.append((case, size or "-", m, spread(a), spread(b), ratio))
    return markdown_table(("case", "size", "metric", f"{numerator} ms", f"{denominator} ms",
                           f"{numerator}/{denominator}"), rows)


# -- plots -------------------------------------------------------------------------------------


def have_matplotlib() -> bool:
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def bar_plot(path: Path, title: str, groups: Sequence[str], series: dict[str, Sequence[float]], ylabel: str,
             errors: dict[str, Sequence[tuple[float, float]]] | None = None, log: bool = False,
             hline: float | None = None) -> Path:
    """Grouped bars: one group per label, one bar per series; error bars from (p10, p90). Small PNG."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 3.6), dpi=80)
    width = 0.8 / max(1, len(series))
    for i, (name, values) in enumerate(series.items()):
        xs = [g + (i - (len(series) - 1) / 2) * width for g in range(len(groups))]
        yerr = None
        if errors and name in errors:
            lo = [max(0.0, v - e[0]) for v, e in zip(values, errors[name], strict=True)]
            hi = [max(0.0, e[1] - v) for v, e in zip(values, errors[name], strict=True)]
            yerr = [lo, hi]
        ax.bar(xs, values, width, label=name, yerr=yerr, capsize=2)
    if hline is not None:
        ax.axhline(hline, color="k", linewidth=0.8, linestyle="--")
    ax.set_xticks(range(len(groups)))
    ax.set_xticklabels(groups, rotation=30, ha="right", fontsize=8)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    if log:
        ax.set_yscale("log")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path
