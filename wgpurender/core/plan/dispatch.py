"""The dispatch shape of each compute post pass: workgroup (x, y) and rows of pixels per invocation.

One shape does not suit every pass (issue 31.6): what a pass reads and writes decides which shape keeps the most
loads in flight. The plan resolves a shape per pass once (``PostPass.shape``, shown by ``--explain``); the shape
changes no pixel, only how the image is split into invocations, so both paths keep identical images (the raw
path's post runs as subpasses and has no dispatch). FXAA on the compute path also reads its 3x3 neighbourhood
through a workgroup tile (``PostPass.tile``): each texel of the tile and a one-texel apron loaded once per
workgroup into workgroup memory, not up to nine times per pixel from the texture; with post_intermediate = none
the tone-mapped texels are recomputed once per tile texel instead of at each read.

Measured by ``wgpurender bench post-roofline --shapes`` on the H100 at 3840x2160, median of 50 frames, GPU
timestamps (docs/perf-h100/2026-11-27-post2/probe/; the earlier sweep in docs/perf-h100/2026-11-27-post/ agrees
on the per-pixel passes):

- a per-pixel pass writing 8 bytes a texel (rgba16float, the tonemap before FXAA): 8x8 x2 rows 0.060 ms (82% of a
  copy of its bytes), 32x8 x4 0.088 ms;
- a per-pixel pass writing 4 bytes a texel (final_subpass's tonemap+vignette): 0.046-0.049 ms for every shape of
  2 or 4 rows (32x8 x4 0.048 ms, 80%), 0.085 ms for 8x8 x1;
- FXAA (then vignette) through its tile: 16x8 x2 0.104 ms, 8x8 x2 0.106, 16x16 x2 0.121; untiled, the best
  shape reads 0.132 ms (8x8 x2) and 32x8 x4 0.147 ms;
- FXAA recomputing tonemap (post_intermediate = none) through its tile: 8x8 x1 0.403 ms, 16x16 x1 0.405, 8x8 x2
  0.715; untiled 0.952 ms at best.
"""

from __future__ import annotations

from wgpurender.core.course.formats import BYTES_PER_PIXEL
from wgpurender.core.errors import UserError

Shape = tuple[int, int, int]

WIDE: Shape = (32, 8, 4)
SQUARE: Shape = (8, 8, 2)
# FXAA's tile: 16 x 16 pixels and a one-texel apron, 18 x 18 texels of vec4f = 5.2 KB of workgroup memory (WebGPU's
# default limit is 16 KB)
TILED: Shape = (16, 8, 2)
# the tile of a pass that recomputes the effects before FXAA: 8 x 8 pixels, one row each (every invocation's
# recomputing is ALU work: the more invocations, the better)
RECOMPUTED: Shape = (8, 8, 1)
TILE_APRON = 1


def dispatch_shape(output_format: str, neighbourhood: bool, tiled: bool, recomputes: bool) -> tuple[Shape, str]:
    """(shape, why) of a compute post pass writing ``output_format``; ``neighbourhood``: its first effect reads
    neighbours; ``tiled``: it reads them through a workgroup tile (FXAA); ``recomputes``: it recomputes the steps
    before that effect per texel (a prelude)."""
    if tiled:
        shape = RECOMPUTED if recomputes else TILED
        w, h = shape[0], shape[1] * shape[2]
        how = "recomputes" if recomputes else "loads"
        rest = "recomputed from the input" if recomputes else "read from the texture"
        return shape, (f"each workgroup {how} its {w}x{h} tile and a {TILE_APRON}-texel apron once into workgroup "
                       f"memory, which the 3x3 neighbourhood reads; taps outside it are {rest}")
    if neighbourhood:
        return SQUARE, "a neighbourhood pass: square workgroups keep the neighbours' rows in cache"
    if BYTES_PER_PIXEL.get(output_format, 4) >= 8:
        return SQUARE, f"a per-pixel pass writing {output_format} ({BYTES_PER_PIXEL[output_format]} bytes a texel)"
    return WIDE, f"a per-pixel pass writing {output_format}: wide rows, 4 per invocation"


def shape_text(shape: Shape) -> str:
    return f"{shape[0]}x{shape[1]} x{shape[2]} rows"


TILE_BYTES_LIMIT = 16384  # WebGPU's default maxComputeWorkgroupStorageSize, what the device is made with
TEXEL_BYTES = 16  # a vec4f per tile texel


def tile_fits(shape: Shape) -> bool:
    """Whether a tiled pass's workgroup memory with ``shape`` stays within WebGPU's default limit."""
    w, h = tile_texels(shape)
    return w * h * TEXEL_BYTES <= TILE_BYTES_LIMIT


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
        if len(parts) != 3 or not all(p.isdigit() for p in parts):
            raise UserError(f"--shapes {text!r}: {item.strip()!r} is not WxHxR (workgroup width, height, rows per "
                            "invocation), e.g. 16x8x2; separate shapes with commas")
        w, h, r = (int(p) for p in parts)
        if not (w >= 1 and h >= 1 and w * h <= MAX_INVOCATIONS and 1 <= r <= MAX_ROWS):
            raise UserError(f"--shapes {text!r}: {item.strip()!r} needs W*H between 1 and {MAX_INVOCATIONS} "
                            f"invocations (WebGPU's default limit) and 1 to {MAX_ROWS} rows")
        shapes.append((w, h, r))
    return tuple(dict.fromkeys(shapes))
