"""The accuracy run as files: accuracy.csv, accuracy.md and accuracy_pareto.png (matplotlib, optional)."""

from __future__ import annotations

import csv
import math
from pathlib import Path

from wgpurender.bench.accuracy_floor import BELOW
from wgpurender.bench.accuracy_knobs import GROUND_TRUTH
from wgpurender.bench.accuracy_run import DEPTH_STRESS, AccuracyRun, Row, unique_rows
from wgpurender.bench.report import have_matplotlib, markdown_table

CSV_COLUMNS = (
    "scene", "sweep", "level", "msaa", "ss", "format", "filter", "depth", "render_size",
    "flip_mean", "psnr_db", "flip_vs_knob_top", "psnr_vs_knob_top", "wrong_pixels",
    "gpu_ms_median", "gpu_ms_p10", "gpu_ms_p90", "wall_ms_median", "wall_ms_p10", "wall_ms_p90", "frames",
    "pareto", "timing", "note",
)
PLOT_NAME = "accuracy_pareto.png"


def _num(value: float | None, digits: int = 4) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, float) and math.isinf(value):
        return "inf"
    return f"{value:.{digits}f}"


def csv_row(r: Row) -> dict:
    s, m = r.case.settings, r.m
    gpu = m.gpu
    return {
        "scene": r.case.scene, "sweep": r.case.sweep, "level": r.case.level, "msaa": s.msaa, "ss": s.ss,
        "format": s.format, "filter": s.filter, "depth": s.depth,
        "render_size": f"{m.render_size[0]}x{m.render_size[1]}",
        "flip_mean": _num(r.flip, 5), "psnr_db": _num(r.psnr, 2), "flip_vs_knob_top": _num(r.flip_isolated, 5),
        "psnr_vs_knob_top": _num(r.psnr_isolated, 2),
        "wrong_pixels": "" if r.wrong_pixels is None else r.wrong_pixels,
        "gpu_ms_median": _num(gpu.median if gpu else None, 3), "gpu_ms_p10": _num(gpu.p10 if gpu else None, 3),
        "gpu_ms_p90": _num(gpu.p90 if gpu else None, 3), "wall_ms_median": _num(m.wall.median, 3),
        "wall_ms_p10": _num(m.wall.p10, 3), "wall_ms_p90": _num(m.wall.p90, 3), "frames": m.wall.n,
        "pareto": "yes" if r.pareto else "", "timing": BELOW if r.below_floor else "", "note": r.case.note,
    }


def write_csv(run: AccuracyRun, path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        for r in run.rows:
            writer.writerow(csv_row(r))
    return path


def _ms(stats, below: bool = False) -> str:
    if stats is None:
        return "-"
    if below:
        return BELOW
    fmt = (lambda v: f"{v:.1f}") if stats.median < 1000 else (lambda v: f"{v:.0f}")
    return f"{fmt(stats.median)} ({fmt(stats.p10)}..{fmt(stats.p90)})"


def _times(r: Row) -> tuple[str, str]:
    """GPU and wall cells; under the noise floor the time the front weighs (GPU where measured) says so."""
    below = r.below_floor
    return _ms(r.m.gpu, below), _ms(r.m.wall, below and r.m.gpu is None)


def _psnr(v: float) -> str:
    return "inf" if math.isinf(v) else ("-" if math.isnan(v) else f"{v:.2f}")


def _flip(v: float) -> str:
    return "-" if math.isnan(v) else f"{v:.4f}"


def markdown(run: AccuracyRun, plot: Path | None) -> str:
    c = run.config
    w, h = c.base_size
    gt = GROUND_TRUTH
    lines = [
        "# Accuracy against time",
        "",
        f"Command: `{c.command}`  ",
        f"Adapter: {run.adapter}  ",
        f"Scene: `{c.scene_path}`, base size {w}x{h}; per setting {c.warmup} warm-up + {c.frames} timed frames, "
        f"spread over {c.rounds} round(s) through all settings; run took {run.seconds:.0f} s.",
        "",
        f"Ground truth (final scene): {gt.label()} = msaa {gt.msaa}, {gt.format}, {gt.filter}, {gt.depth}, rendered "
        f"at {w * gt.ss}x{h * gt.ss} and area-averaged in linear light to {w}x{h}. Depth-stress rows: the analytic "
        "image (the near quad everywhere).",
        "Error: FLIP mean (0 = identical) and PSNR against the ground truth; 'knob top': FLIP against the same "
        "setting with the swept knob at its highest level (the knob's own effect). Time per frame: GPU = sum of "
        "the passes' timestamp queries, wall = record + submit + wait; median (p10..p90). Supersampled rows are "
        "timed at the large size; the downsampling (here numpy) is not in the time.",
        "",
    ]
    final = [r for r in run.rows if r.case.scene != DEPTH_STRESS]
    header = ("sweep", "level", "setting", "render", "FLIP", "PSNR dB", "FLIP vs knob top", "GPU ms", "wall ms",
              "Pareto")
    body = [(r.case.sweep, r.case.level, r.case.settings.label() + (f" ({r.case.note})" if r.case.note else ""),
             f"{r.m.render_size[0]}x{r.m.render_size[1]}", _flip(r.flip), _psnr(r.psnr), _flip(r.flip_isolated),
             *_times(r), "**front**" if r.pareto else "") for r in final]
    lines += ["## Final scene", "", markdown_table(header, body), ""]
    stress = [r for r in run.rows if r.case.scene == DEPTH_STRESS]
    if stress:
        n = w * h
        body = [(r.case.level, f"{r.wrong_pixels} / {n}", _flip(r.flip), _psnr(r.psnr), *_times(r))
                for r in stress]
        lines += ["## Depth stress (near 0.01, far 1e5, quads 0.05% apart at 1e4, far one drawn first)", "",
                  markdown_table(("depth", "wrong pixels", "FLIP", "PSNR dB", "GPU ms", "wall ms"), body), ""]
    front = sorted((r for r in unique_rows(final) if r.pareto), key=lambda r: r.time_ms)
    if front:
        lines += ["Pareto front (no other setting is both faster and more accurate), by time: "
                  + "; ".join(f"{r.case.settings.label()} ({r.time_ms:.1f} ms, FLIP {r.flip:.4f})" for r in front),
                  ""]
    lines.append(f"![error against time]({plot.name})" if plot else
                 "Plot skipped: matplotlib is not installed (pip install 'wgpurender[bench]').")
    lines += [f"- {note}" for note in run.notes + ([run.floor.describe()] if run.floor else [])]
    return "\n".join(lines) + "\n"


def short_label(r: Row) -> str:
    return f"{r.case.sweep}={r.case.level}" if r.case.sweep != "lowest" else "lowest"


def _merged_labels(rows: list[Row]) -> dict[tuple[float, float], list[str]]:
    """One annotation per spot: settings whose images are equal and times within 5% share one label."""
    spots: dict[tuple[float, float], list[str]] = {}
    for r in rows:
        t = max(r.time_ms, 1e-9)
        spot = next((k for k in spots if k[1] == r.flip and abs(math.log(max(k[0], 1e-9) / t)) < 0.05), None)
        spots.setdefault(spot or (r.time_ms, r.flip), []).append(short_label(r))
    return spots


def write_plot(run: AccuracyRun, path: Path) -> Path:
    """FLIP against time (log) for every distinct final-scene setting; the Pareto front joined and ringed."""
    from wgpurender.bench.report import _pyplot

    plt = _pyplot()
    rows = unique_rows([r for r in run.rows if r.case.scene != DEPTH_STRESS and r.case.sweep != "ground truth"])
    gpu = all(r.m.gpu is not None for r in rows)
    fig, ax = plt.subplots(figsize=(8.5, 5.2), dpi=90)
    sweeps = list(dict.fromkeys(r.case.sweep for r in rows))
    markers = "osD^v<>ph*"
    for i, sweep in enumerate(sweeps):
        pts = [r for r in rows if r.case.sweep == sweep]
        ax.scatter([r.time_ms for r in pts], [r.flip for r in pts], marker=markers[i % len(markers)], s=30,
                   label=sweep, zorder=3)
    texts = [ax.annotate(", ".join(labels), (t, e), textcoords="offset points", xytext=(4, 3), fontsize=6.5)
             for (t, e), labels in _merged_labels(rows).items()]
    front = sorted((r for r in rows if r.pareto), key=lambda r: r.time_ms)
    if front:
        ax.step([r.time_ms for r in front], [r.flip for r in front], where="post", color="k", linewidth=1,
                label="Pareto front", zorder=2)
        ax.scatter([r.time_ms for r in front], [r.flip for r in front], s=110, facecolors="none", edgecolors="k",
                   zorder=4)
    ax.set_xscale("log")
    ax.set_xlabel(f"{'GPU' if gpu else 'wall'} time per frame, ms (median, log scale)")
    ax.set_ylabel("FLIP mean against the ground truth")
    w, h = run.config.base_size
    ax.set_title(f"{run.config.scene_path.name} at {w}x{h}: error against time ({run.adapter.split(' (')[0]})",
                 fontsize=9)
    ax.grid(True, which="both", linewidth=0.3)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    _spread_labels(fig, texts)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path


def _spread_labels(fig, texts: list, step_points: float = 7.0, rounds: int = 60) -> None:
    """Move point labels up or down (in steps of ``step_points``) until no two overlap: settings of close error
    and time otherwise print on top of each other."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for _ in range(rounds):
        boxes = [t.get_window_extent(renderer) for t in texts]
        moved = False
        pairs = [(a, b) for a in range(len(texts)) for b in range(a + 1, len(texts))]
        for i, j in pairs:
            if boxes[i].overlaps(boxes[j]):
                lower = j if boxes[j].y0 < boxes[i].y0 or (boxes[j].y0 == boxes[i].y0 and j > i) else i
                x, y = texts[lower].xyann
                texts[lower].xyann = (x, y - step_points)
                boxes[lower] = texts[lower].get_window_extent(renderer)
                moved = True
        if not moved:
            return


def write_reports(run: AccuracyRun, out_dir: Path) -> dict[str, Path]:
    """accuracy.csv, accuracy.md and (with matplotlib) accuracy_pareto.png in ``out_dir``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = {"csv": write_csv(run, out_dir / "accuracy.csv")}
    plot = write_plot(run, out_dir / PLOT_NAME) if have_matplotlib() else None
    if plot:
        paths["plot"] = plot
    md = out_dir / "accuracy.md"
    md.write_text(markdown(run, plot))
    paths["markdown"] = md
    return paths
