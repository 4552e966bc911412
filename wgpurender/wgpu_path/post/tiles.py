"""FXAA's workgroup tiles on the compute path: the WGSL that fills one and the reads that take it.

A tiled FXAA pass first fills workgroup memory with the workgroup's pixels and a one-texel apron, then each
invocation runs FXAA reading its neighbourhood from there instead of from the texture. The plan says which tile a
pass uses (``PostPass.tile``, core/plan/dispatch.py):

- ``texels``: a vec4f per texel, filled with ``tile_source`` (the stored texel or, with post_intermediate =
  none, the effects before FXAA recomputed), so every ``fxaa_texel`` read of a neighbour, the recomputed bilinear
  taps included, takes it;
- ``luma``: one f32 per texel, the luma FXAA computes from it (``luma_of``), for a pass that reads a stored image
  (no prelude). FXAA's first step reads five lumas of every pixel and its 3x3 step four more: computed once per
  texel here, not at each read, and read as 4 bytes instead of a texture fetch. Each invocation loads its own
  pixels first and keeps their colours in registers (FXAA's centre, and the colour written where it stops
  early), then the apron, shared out among the invocations. The edge search and the final tap stay bilinear
  samples of the texture.

Either way, a read outside the tile takes the texture (or recomputes), with the same function on the same texel
value: the image is the untiled one's, byte for byte (tests/test_post_dispatch.py).
"""

from __future__ import annotations

from wgpurender.core.plan.dispatch import TILE_APRON, tile_texels

# ``texels``: fxaa_texel through the tile (tile_source fills it; cs_main below)
TEXELS_READS = """
var<workgroup> tile: array<vec4f, TILE_N>;
var<private> tile_origin: vec2i;  // the texel at tile[0]: the workgroup's first pixel minus the apron

fn fxaa_texel(p: vec2i) -> vec4f {
    let t = p - tile_origin;
    if t.x >= 0 && t.y >= 0 && t.x < TILE_Wi && t.y < TILE_Hi {
        return tile[t.y * TILE_Wi + t.x];
    }
    return tile_source(p);
}

fn fxaa_luma(p: vec2i) -> f32 {
    return luma_of(fxaa_texel(p).rgb);
}
"""

# ``luma``: the lumas through the tile; the centre's colour is the one cs_main loaded for its pixel
LUMA_READS = """
var<workgroup> luma_tile: array<f32, TILE_N>;
var<private> tile_origin: vec2i;  // the texel at luma_tile[0]: the workgroup's first pixel minus the apron
var<private> own_p: vec2i;         // the pixel this invocation is drawing, and its texel (loaded once)
var<private> own_texel: vec4f;

fn fxaa_texel(p: vec2i) -> vec4f {
    if all(p == own_p) {
        return own_texel;
    }
    return tile_source(p);
}

fn fxaa_luma(p: vec2i) -> f32 {
    let t = p - tile_origin;
    if t.x >= 0 && t.y >= 0 && t.x < TILE_Wi && t.y < TILE_Hi {
        return luma_tile[t.y * TILE_Wi + t.x];
    }
    return luma_of(tile_source(p).rgb);
}
"""

# both tiles' cs_main begins so: the workgroup's first pixel and the tile's origin, one apron up and left
MAIN_HEAD = """
@group(0) @binding(3) var dst: texture_storage_2d<FORMAT, write>;

@compute @workgroup_size(WX, WY)
fn cs_main(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_id) local: vec3u,
           @builtin(local_invocation_index) index: u32) {
    let size = textureDimensions(src);
    let corner = group.xy * vec2u(WXu, PIX_Hu);
    tile_origin = vec2i(corner) - vec2i(APRON, APRON);
"""

TEXELS_MAIN = MAIN_HEAD + """    for (var i = index; i < TILE_Nu; i += WXu * WYu) {
        tile[i] = tile_source(tile_origin + vec2i(i32(i % TILE_Wu), i32(i / TILE_Wu)));
    }
    workgroupBarrier();
    for (var k = 0u; k < ROWSu; k++) {
        let xy = corner + vec2u(local.x, local.y * ROWSu + k);
        if xy.x < size.x && xy.y < size.y {
            let p = vec2i(xy);
            textureStore(dst, p, pass_color(p, vec2f(xy) + vec2f(0.5), vec2f(size)));
        }
    }
}
"""

LUMA_MAIN = """
// Texel j of the tile's apron (tile coordinates): the rows above the pixels, the rows below, then the
// columns left and right of the pixel rows.
fn apron_texel(j: u32) -> vec2u {
    let band = APRONu * TILE_Wu;
    if j < 2u * band {
        let r = j / TILE_Wu;
        return vec2u(j % TILE_Wu, select(r, r + PIX_Hu, r >= APRONu));
    }
    let c = j - 2u * band;
    let col = c / PIX_Hu;
    return vec2u(select(col, col + WXu, col >= APRONu), APRONu + c % PIX_Hu);
}
""" + MAIN_HEAD + """    var own: array<vec4f, ROWS>;  // this invocation's pixels (clamped to the image, as the apron)
    for (var k = 0u; k < ROWSu; k++) {
        let t = vec2u(local.x, local.y * ROWSu + k) + vec2u(APRONu, APRONu);
        own[k] = tile_source(tile_origin + vec2i(t));
        luma_tile[t.y * TILE_Wu + t.x] = luma_of(own[k].rgb);
    }
    for (var j = index; j < APRON_Nu; j += WXu * WYu) {
        let t = apron_texel(j);
        luma_tile[t.y * TILE_Wu + t.x] = luma_of(tile_source(tile_origin + vec2i(t)).rgb);
    }
    workgroupBarrier();
    for (var k = 0u; k < ROWSu; k++) {
        let xy = corner + vec2u(local.x, local.y * ROWSu + k);
        if xy.x < size.x && xy.y < size.y {
            own_p = vec2i(xy);
            own_texel = own[k];
            textureStore(dst, own_p, pass_color(own_p, vec2f(xy) + vec2f(0.5), vec2f(size)));
        }
    }
}
"""

READS = {"texels": TEXELS_READS, "luma": LUMA_READS}
MAINS = {"texels": TEXELS_MAIN, "luma": LUMA_MAIN}


def _fill(text: str, shape: tuple[int, int, int]) -> str:
    wx, wy, rows = shape
    w, h = tile_texels(shape)
    apron = 2 * TILE_APRON * w + 2 * TILE_APRON * wy * rows
    # APRON_N before APRON (a name inside another is replaced after it)
    for name, value in (("TILE_N", w * h), ("TILE_W", w), ("TILE_H", h), ("PIX_H", wy * rows), ("APRON_N", apron),
                        ("APRON", TILE_APRON), ("ROWS", rows), ("WX", wx), ("WY", wy)):
        text = text.replace(name, str(value))
    return text


def tiled_reads(kind: str, shape: tuple[int, int, int]) -> str:
    """fxaa_texel and fxaa_luma through a ``kind`` tile (a key of :data:`READS`) for a pass of ``shape``."""
    return _fill(READS[kind], shape)


def tiled_main(kind: str, shape: tuple[int, int, int], output_format: str) -> str:
    """cs_main filling a ``kind`` tile, then drawing its pixels as COMPUTE_MAIN does (shaders.py)."""
    return _fill(MAINS[kind], shape).replace("FORMAT", output_format)
