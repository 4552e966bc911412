"""The dispatch shape of each compute post pass: workgroup (x, y) and rows of pixels per invocation.

One shape does not suit every pass (issue 31.6): what a pass reads and writes decides which shape keeps the most
loads in flight. The plan resolves a shape per pass once (``PostPass.shape``, shown by ``--explain``); the shape
changes no pixel, only how the image is split into invocations, so both paths keep identical images (the raw
path's post runs as subpasses and has no dispatch). Measured by ``wgpurender bench post-roofline --shapes`` on
the H100 at 3840x2160 (docs/perf-h100/2026-11-27-post/roofline and docs/perf-h100/2026-11-27-post2/):

- a per-pixel pass writing 8 bytes a texel (rgba16float, the tonemap pass before FXAA): 8x8 x2 rows 0.060 ms
  (81% of a copy of its bytes), 32x8 x4 0.088 ms;
- a per-pixel pass writing 4 bytes a texel (final_subpass's fused tonemap+vignette): 32x8 x4 0.047 ms, 1.23x the
  copy (8x8 x2 reads 0.048 ms);
- a neighbourhood pass (FXAA, then vignette): 8x8 x2 0.073 ms, 32x8 x4 0.075 ms, 8x8 x1 0.125 ms;
- FXAA on the compute path reads its 3x3 neighbourhood through a workgroup tile (:data:`TILED`: each texel
  loaded once per workgroup into workgroup memory, not five times per pixel from the texture), and a pass that
  recomputes the effects before FXAA for every texel it reads (post_intermediate = none) recomputes each texel
  of the tile once: the shape is the tile's.
"""

from __future__ import annotations

from wgpurender.core.course.formats import BYTES_PER_PIXEL

Shape = tuple[int, int, int]

WIDE: Shape = (32, 8, 4)
SQUARE: Shape = (8, 8, 2)
# The tile of a recomputing pass: 16 x 32 pixels, a one-texel apron (18 x 34 texels of vec4f = 9.8 KB of
# workgroup memory, under WebGPU's 16 KB floor).
TILED: Shape = (16, 16, 2)
TILE_APRON = 1


def dispatch_shape(output_format: str, neighbourhood: bool, tiled: bool, recomputes: bool) -> tuple[Shape, str]:
    """(shape, why) of a compute post pass writing ``output_format``; ``neighbourhood``: its first effect reads
    neighbours; ``tiled``: it reads them through a workgroup tile (FXAA); ``recomputes``: it recomputes the steps
    before that effect per texel (a prelude)."""
    if tiled:
        w, h = TILED[0], TILED[1] * TILED[2]
        how = "recomputes" if recomputes else "loads"
        rest = "recomputed from the input" if recomputes else "read from the texture"
        return TILED, (f"each workgroup {how} its {w}x{h} tile and a {TILE_APRON}-texel apron once into workgroup "
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
