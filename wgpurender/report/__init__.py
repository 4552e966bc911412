"""The visual course report: one static page where each course step stands with its two images and their code.

``wgpurender report -o DIR`` (or :func:`build_report`) writes ``DIR/index.html`` and its PNG
files: a self-contained site (no network, no script) that any browser opens from disk.
Per course step, in course order:

- the step's words (the stage's summary and its module docstring; a scene's description);
- the wgpu image and the raw-Vulkan image side by side, the difference heatmap
  (wgpurender/core/verdict/compare.py) with its colour scale, PSNR and FLIP;
- the median GPU time and frame time on both paths (the benchmark runners of
  wgpurender/bench/frames.py, a few frames each: a quick look, not the benchmark);
- the code that makes the step on both paths, side by side, highlighted (Pygments) and linked
  to a highlighted listing of the whole file written beside the page;
- the concept rows of wgpurender/concepts.py that the step teaches, with the code
  locations on both paths as ``file:line``;
- for scenes, the render plan (``render SCENE.toml --explain``), collapsed.

Then the accuracy Pareto plot and the hard cases against exact answers, both measured in
the run (a quick variant). Like bench/, this package may import both paths. ``Step.links``
is the hook for more views of a step (e.g. a live page): rendered as links under its words.

Modules: ``steps`` (rendering, comparing and timing one step), ``timings`` (the frame
timers for scenes), ``concept_rows`` (which concept rows belong to which step, code
locations as file:line), ``code`` (the excerpts and listings), ``extras`` (the accuracy
and hard-case measurements), ``page`` (HTML).
"""

from wgpurender.report.build import build_report

__all__ = ["build_report"]
