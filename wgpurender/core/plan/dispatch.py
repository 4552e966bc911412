"""The dispatch shape of each compute post pass: workgroup (x, y) and rows of pixels per invocation.

One shape does not suit every pass (issue 31.6): what a pass reads and writes decides which shape keeps the most
loads in flight. The plan resolves a shape per pass once (``PostPass.shape``, shown by ``--explain``); the shape
changes no pixel, only how the image is split into invocations, so both paths keep identical images (the raw
path's post runs as subpasses and has no dispatch). A pass that recomputes the effects before FXAA for every
texel it reads (post_intermediate = none) does it through a workgroup tile (``PostPass.tile``): each texel of
the tile and a one-texel apron recomputed once into workgroup memory, not at each of FXAA's reads.

Measured by ``wgpurender bench post-roofline --shapes`` on two H100 hosts at 3840x2160, median of 50 frames, GPU
timestamps, each a sweep in one run (docs/perf-h100/2026-11-27-post2/: ``probe/`` on one host, ``final/`` on
another):

- a per-pixel pass writing 8 bytes a texel (rgba16float, the tonemap before FXAA): 8x8 x2 rows 0.060 ms on
  both (81-82% of a copy of its bytes), 32x8 x4 0.088 ms;
- a per-pixel pass writing 4 bytes a texel (final_subpass's tonemap+vignette): 0.046-0.049 ms for every shape of
  2 or 4 rows (32x8 x4 0.047-0.048 ms, 80-81%), 0.085 ms for 8x8 x1;
- FXAA (then vignette) reading the stored image: 8x8 x2 0.073 ms (final) / 0.132 (probe), 32x8 x4 0.075 /
  0.147. Through a workgroup tile it reads 0.103-0.106 ms on both hosts: slower where the texture reads are
  fast, so FXAA reads the texture (the tile stays a ``--shapes`` variant);
- FXAA reading the stored image, interleaved in one process with its SM clock read each round
  (docs/perf-h100/2026-11-27-post4/, ``benchmarks/post_interleave.py``): untiled 8x8 x2 0.0735 ms at 1980 MHz,
  0.126 at 1080 MHz (the clock fell mid-run): the pass follows the SM clock, it is not bound by memory. Through
  the tile of lumas (each texel's luma once, 4 bytes a texel) it is slower at every clock and shape: the median
  per-round ratio to untiled 1.41x (16x16 x1) to 1.61x (8x8 x4), 1.58x with 8x8 x2; the texel tile 1.40x. So the
  texture fetches were not the bound either: FXAA reads the texture (both tiles stay ``--shapes`` variants);
- FXAA reading the stored image over an edge list (wgpurender/bench/fxaa_variants/edge_list.py;
  docs/perf-h100/2026-11-27-post5/):
  a pass over every pixel writes those off edges and lists the 3.1% that are edges, a second runs the edge search
  on the listed pixels only (an indirect dispatch). Interleaved at 1980 MHz it is slower at every shape: 0.089 ms
  at best (16x8 x4) against 0.0735 untiled, 0.108 with 8x8 x2. The first dispatch alone (the contrast test over
  every pixel) takes 0.071 ms: the edge search was never the cost. The plan keeps the one dispatch (the edge list
  is a ``--shapes`` variant);
- FXAA taking its lumas from the intermediate's alpha (wgpurender/bench/fxaa_variants/luma_alpha.py;
  docs/perf-h100/2026-11-27-post6/):
  the tonemap pass stores them at no cost, FXAA's contrast test gathers them (two textureGathers and the centre
  texel instead of five loads and five square roots), byte-equal: 0.0717 ms against 0.0735 at 1980 MHz (8x8 x2),
  2.5%, and it writes alpha 1, which the chain's output may not have. The plan keeps main's pass (a benchmark case);
- FXAA recomputing tonemap (post_intermediate = none) through its tile: 8x8 x1 0.318 / 0.403 ms, 8x8 x2
  0.210 / 0.715; untiled 0.395-0.618 / 0.952-1.342: the tile wins on both hosts, the shape's ranking differs.
"""

from __future__ import annotations

from wgpurender.core.course.formats import BYTES_PER_PIXEL
from wgpurender.core.errors import UserError

Shape = tuple[int, int, int]

WIDE: Shape = (32, 8, 4)
SQUARE: Shape = (8, 8, 2)
# the tile of a pass that recomputes the effects before FXAA: 8 x 8 pixels and a one-texel apron, 10 x 10 texels
# of vec4f = 1.6 KB of workgroup memory (WebGPU's default limit is 16 KB); one row each: the recomputing is ALU
# work, and the more invocations share it the better
RECOMPUTED: Shape = (8, 8, 1)
TILE_APRON = 1


def dispatch_shape(output_format: str, neighbourhood: bool, recomputes: bool) -> tuple[Shape, str, str]:
    """(shape, why, tile) of a compute post pass writing ``output_format``; ``neighbourhood``: its first effect
    reads neighbours; ``recomputes``: it recomputes the steps before that effect per texel (a prelude), through a
    workgroup tile. ``tile``: the workgroup tile its reads go through (:data:`TILE_KINDS`), "" for none."""
    if recomputes:
        w, h = RECOMPUTED[0], RECOMPUTED[1] * RECOMPUTED[2]
        return RECOMPUTED, (f"each workgroup recomputes its {w}x{h} tile and a {TILE_APRON}-texel apron once into "
                            "workgroup memory, which FXAA's reads take where they fall in it; the others recompute "
                            "from the input"), "texels"
    if neighbourhood:
        return SQUARE, "a neighbourhood pass: square workgroups keep the neighbours' rows in cache", ""
    if BYTES_PER_PIXEL.get(output_format, 4) >= 8:
        return SQUARE, (f"a per-pixel pass writing {output_format} ({BYTES_PER_PIXEL[output_format]} bytes a "
                        "texel)"), ""
    return WIDE, f"a per-pixel pass writing {output_format}: wide rows, 4 per invocation", ""


def shape_text(shape: Shape) -> str:
    return f"{shape[0]}x{shape[1]} x{shape[2]} rows"


TILE_BYTES_LIMIT = 16384  # WebGPU's default maxComputeWorkgroupStorageSize, what the device is made with
# FXAA's workgroup tiles (wgpu_path/post/tiles.py) and the bytes of one texel of each: a vec4f colour, or its luma
TEXEL_BYTES = {"texels": 16, "luma": 4}
TILE_KINDS = tuple(TEXEL_BYTES)


def tile_fits(shape: Shape, kind: str = "texels") -> bool:
    """Whether a tiled pass's workgroup memory with ``shape`` and a ``kind`` tile stays within WebGPU's default
    limit."""
    w, h = tile_texels(shape)
    return w * h * TEXEL_BYTES[kind] <= TILE_BYTES_LIMIT


def tile_texels(shape: Shape) -> tuple[int, int]:
    """(width, height) in texels of a tiled pass's workgroup tile, apron included."""
    return shape[0] + 2 * TILE_APRON, shape[1] * shape[2] + 2 * TILE_APRON


MAX_INVOCATIONS = 256  # WebGPU's default maxComputeInvocationsPerWorkgroup
MAX_ROWS = 16


def parse_shapes(text: str) -> tuple[Shape, ...]:
    """``WxHxR[,WxHxR...]`` (workgroup width, height, rows per invocation) for ``bench post-roofline --shapes``."""
    shapes = []
    for item in text.split(","):
        parts = item.strip().lower().split("x")
        if len(parts) != 3 or not all(p.isdecimal() for p in parts):  # int()'s digits: '²' isdigit, not decimal
            raise UserError(f"--shapes {text!r}: {item.strip()!r} is not WxHxR (workgroup width, height, rows per "
                            "invocation), e.g. 16x8x2; separate shapes with commas")
        w, h, r = (int(p) for p in parts)
        if not (w >= 1 and h >= 1 and w * h <= MAX_INVOCATIONS and 1 <= r <= MAX_ROWS):
            raise UserError(f"--shapes {text!r}: {item.strip()!r} needs W*H between 1 and {MAX_INVOCATIONS} "
                            f"invocations (WebGPU's default limit) and 1 to {MAX_ROWS} rows")
        shapes.append((w, h, r))
    return tuple(dict.fromkeys(shapes))
