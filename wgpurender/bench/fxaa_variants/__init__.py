"""FXAA passes measured against the plan's and not drawn by it (issue 31.6): each draws the plan's image byte for
byte, and each lost on the H100 (docs/benchmarks.md, the issue-31.6 passes). They live with the benchmarks that
time them (`bench post-roofline --shapes`, benchmarks/post_interleave.py), so `wgpu_path/post/` holds only what
the plan draws.

- edge_list.py, edge_wgsl.py: FXAA over an edge list (a marking dispatch, an indirect one over the edges);
- luma_alpha.py: FXAA reading its lumas from the intermediate's alpha through textureGather.
"""
