"""The visual course report: one static page where each course step stands with its two images and their code.

``wgpurender report -o DIR`` (or :func:`build_report`) writes ``DIR/index.html`` and its PNG
files: a self-contained site (no network, no script) that any browser opens from disk.
Per course step, in course order:

- the step's words (the stage's summary and its module docstring; a scene's description);
- the wgpu image and the raw-Vulkan image side by side, the difference heatmap
  (wgpurender/core/compare.py) with its colour scale, PSNR and FLIP;
- the median GPU time and frame time on both paths (the benchmark runners of
  wgpurender/bench/frames.py, a few frames each: a quick look, not the benchmark);
- the concept rows of wgpurender/concepts.py that the step teaches, with the code
  locations on both paths as ``file:line``;
- for scenes, the render plan (``render SCENE.toml --explain``).

Then the accuracy Pareto plot (docs/img/accuracy_pareto.png) and the measured hard
cases' table (docs/numerics.md). Like bench/, this package may import both paths.

Modules: ``steps`` (rendering, comparing and timing one step), ``timings`` (the frame
timers for scenes), ``concept_rows`` (which concept rows belong to which step, code
locations as file:line), ``extras`` (the Pareto plot and the hard cases), ``page`` (HTML).
"""

from wgpurender.report.build import build_report

__all__ = ["build_report"]
