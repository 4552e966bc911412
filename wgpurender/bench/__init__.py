"""Benchmarks: how fast the wgpu path is against its peers (the raw-Vulkan path, the C++ tutorial's numbers).

One module per measurement family, each returning :class:`~wgpurender.bench.report.Result` rows:

- :mod:`.frames`: frame time of every stage, wgpu against raw Vulkan on the same scene; CPU time to
  encode and submit; readback cost;
- :mod:`.scene`: the final scene frame by frame (``final_subpass.toml`` on both paths: the raw path's
  subpass refuses final.toml's FXAA);
- :mod:`.post`: the cost of each post effect, the post pass's cost taken apart (format, sampler,
  quad, load op, readback), and wgpu MSAA + one effect against the raw path's msaa-post subpass;
- :mod:`.objects`: many tiny objects through dynamic offsets, immediates, instancing and bundles;
- :mod:`.startup`: first-frame time (shader compilation, pipeline creation) with and without caches,
  each run in a fresh process;
- :mod:`.perf`: runs them all (``wgpurender bench perf``); :mod:`.report`: CSV, markdown, plots.

Numbers from a shared machine are noisy: every family reports a median with the 10th and 90th
percentiles, and comparisons are ratios taken within one run.
"""

import wgpurender.wgpu_path  # noqa: E402, F401  $WGPURENDER_BINDING's wgpu installed before a bench module imports wgpu
