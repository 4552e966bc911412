"""FXAA: luma-based post-process anti-aliasing, in the style of FXAA 3.11 (quality).

The algorithm is explained step by step in shaders_wgsl/post_fxaa.wgsl. It needs
bilinear filtering of its input (the edge search samples between pixels), so the
input must be a filterable format: rgba16float or 8-bit, not rgba32float.

Why two draws and a depth attachment (issue 7): FXAA leaves most pixels alone (flat regions
exit early), but llvmpipe (lavapipe) compiles a branch into masked code that runs both sides
for every pixel, so the early exit saved nothing: the pass cost the same on a flat image as
on the scene (42 vs 44 ms at 1280x720), 7-8x tonemap. What llvmpipe does skip is the whole
shader for a block of pixels that fails an early depth test. So draw 1 (``fs_mark``) copies
every pixel and writes depth 1 on edge pixels, 0 elsewhere; draw 2 (``fs_main``, the full
FXAA, at depth 0 with compare "less") then runs only for blocks holding an edge pixel and
writes only edge pixels. The output is bit-identical to the single draw (the same code makes
the same decision), at 17 ms flat / 26 ms on the final scene. On a hardware GPU the branch was
already cheap; there the first draw adds one texel copy per pixel.
"""

from __future__ import annotations

from .base import DrawStep, Param, PostEffect


class Fxaa(PostEffect):
    name = "fxaa"
    summary = "fast approximate anti-aliasing (FXAA 3.11-style, luma based)"
    shader = "post_fxaa.wgsl"
    filtering = True
    depth_format = "depth16unorm"
    steps = (
        DrawStep("fs_mark", depth_compare="always", depth_write=True),
        DrawStep("fs_main", depth_compare="less"),
    )
    params_spec = (
        Param("subpix", 0.75, "sub-pixel aliasing removal, 0 (off) .. 1 (softer)", lo=0.0, hi=1.0),
        Param("edge_threshold", 0.166, "minimum local contrast relative to the brightest neighbour", lo=0.0, hi=1.0),
        Param("edge_threshold_min", 0.0833, "minimum absolute local contrast (skips dark noise)", lo=0.0, hi=1.0),
    )
