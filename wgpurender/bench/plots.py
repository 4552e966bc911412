"""The perf run's plots (matplotlib, optional): small PNGs for docs/benchmarks.md."""

from __future__ import annotations

from pathlib import Path

from wgpurender.bench.report import Result, bar_plot, ratios


def write_plots(results: list[Result], out_dir: Path) -> dict[str, Path]:
    out: dict[str, Path] = {}
    frame_ratios = ratios([r for r in results if r.family == "frames"], "wgpu", "raw")
    if frame_ratios:
        sizes = sorted({k[2] for k in frame_ratios}, key=lambda s: int(s.split("x")[0]))
        cases = list(dict.fromkeys(k[1] for k in frame_ratios))
        series = {s: [frame_ratios.get(("frames", c, s, "frame_ms"), 0.0) for c in cases] for s in sizes}
        out["frames"] = bar_plot(out_dir / "perf_frames.png", "frame time wgpu / raw Vulkan (1.0 = equal)",
                                 cases, series, "ratio", hline=1.0)
    objects = [r for r in results if r.family == "objects" and r.metric == "frame_ms"]
    if objects:
        modes = list(dict.fromkeys(r.case.split("/")[0] for r in objects))
        counts = sorted({int(r.case.split("/")[1]) for r in objects})
        by = {(r.case.split("/")[0], int(r.case.split("/")[1])): r for r in objects}
        series = {f"{c} objects": [by[(m, c)].median if (m, c) in by else 0.0 for m in modes] for c in counts}
        errors = {f"{c} objects": [(by[(m, c)].p10, by[(m, c)].p90) if (m, c) in by else (0.0, 0.0) for m in modes]
                  for c in counts}
        out["objects"] = bar_plot(out_dir / "perf_objects.png", "many objects: frame time by mode", modes, series,
                                  "ms per frame (log)", errors=errors, log=True)
    post = [r for r in results if r.family in ("post-effects", "post-probe") and r.metric == "gpu_ms"]
    if post:
        labels = [r.case.split(":")[0][:28] for r in post]
        out["post"] = bar_plot(out_dir / "perf_post.png", f"post passes, GPU time ({post[0].size})", labels,
                               {"gpu ms": [r.median for r in post]}, "ms",
                               errors={"gpu ms": [(r.p10, r.p90) for r in post]})
    startup = [r for r in results if r.family == "startup" and r.metric == "total_ms"]
    if startup:
        labels = [f"{r.path}: {r.case.split(': ', 1)[-1]}" for r in startup]
        out["startup"] = bar_plot(out_dir / "perf_startup.png", "process start to first pixels", labels,
                                  {"ms": [r.median for r in startup]}, "ms",
                                  errors={"ms": [(r.p10, r.p90) for r in startup]})
    return out
