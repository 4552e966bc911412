// Shared part of every post pass (wgpurender/wgpu_path/post/): first in the WGSL that
// wgpurender/wgpu_path/post/shaders.py generates for each pass, before the effects' functions.
//
// Vulkan reads the previous pass through an input attachment inside the same
// render pass (subpassLoad). WebGPU has no subpasses, so the previous result is
// an ordinary sampled texture and each effect is its own render pass: the image
// makes a full trip through memory (write, then read) between effects instead of
// staying in tile memory. On tilers that costs bandwidth; on desktop GPUs and on
// lavapipe subpasses are not tile-local anyway, so the cost there is the same.

// The previous pass's result. Effects that only read whole texels use
// textureLoad; FXAA also declares a filtering sampler in its own file.
@group(0) @binding(0) var src: texture_2d<f32>;

struct FullscreenOut {
    @builtin(position) position: vec4f,
};

// One triangle that covers the viewport: NDC (-1,-1), (3,-1), (-1,3).
// Cheaper than a quad (no diagonal seam where two triangles share pixels).
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> FullscreenOut {
    let x = f32((index << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(index & 2u) * 2.0 - 1.0;
    var out: FullscreenOut;
    out.position = vec4f(x, y, 0.0, 1.0);
    return out;
}

// The texel under this fragment (frag position is the pixel centre, x + 0.5).
fn src_texel(frag: vec4f) -> vec4f {
    return textureLoad(src, vec2i(frag.xy), 0);
}

// A texel with clamp-to-edge addressing, for neighbourhood filters.
fn src_clamped(p: vec2i) -> vec4f {
    let last = vec2i(textureDimensions(src)) - vec2i(1, 1);
    return textureLoad(src, clamp(p, vec2i(0, 0), last), 0);
}

// Rec. 709 / sRGB primaries luminance of linear RGB.
const LUMA_709 = vec3f(0.2126, 0.7152, 0.0722);


struct FxaaParams {
    subpix: f32,
    edge_threshold: f32,
    @size(8) edge_threshold_min: f32,
}

struct VignetteParams {
    strength: f32,
    radius: f32,
    @size(8) softness: f32,
}

struct PassParams {
    s0: FxaaParams,
    s1: VignetteParams,
}


@group(0) @binding(2) var<uniform> params: PassParams;

// FXAA in the style of Timothy Lottes' FXAA 3.11 "quality" path, written for
// this project (see wgpurender/wgpu_path/post/shaders.py). Needs post_common.wgsl (prepended).
//
// 1. Local contrast: luma of the pixel and its 4 neighbours; below the
//    threshold the pixel is returned untouched (flat regions stay exact).
//    The fragment pass draws twice (wgpurender/wgpu_path/post/shaders.py): fs_mark writes every
//    pixel untouched and marks edge pixels in a depth attachment, then fs_main
//    runs depth-tested on edge pixels only. On lavapipe that is what makes the
//    early exit real: llvmpipe runs both sides of a branch for every pixel, but
//    skips the whole shader for a block of pixels that fails an early depth test.
// 2. Sub-pixel aliasing: how far the pixel is from the 3x3 average luma gives a
//    blend amount for lone bright/dark pixels.
// 3. Edge direction: horizontal or vertical from second differences, then which
//    side of the pixel the edge lies on (the steeper neighbour).
// 4. Edge search: walk along the edge in both directions (bilinear samples half
//    a pixel off centre, i.e. the average of both sides) until the luma leaves
//    the edge's average; the nearer end decides how far across the edge to
//    shift the final sample.
// 5. One bilinear fetch at the shifted position blends the two sides.
//
// Luma is computed on sqrt(linear luminance), an approximation of perceptual
// lightness: FXAA's thresholds are meant for gamma-encoded values.

@group(0) @binding(1) var src_sampler: sampler;

// Every read of the input goes through fxaa_texel(p) (a texel, clamped to the edge), fxaa_luma(p) (its luma)
// and fxaa_sample(uv) (a bilinear sample), which wgpurender/wgpu_path/post/shaders.py generates: src_clamped and the sampler, or, with
// the knob post_intermediate = none, the effects before FXAA applied to each texel read and the bilinear taps
// computed here from four such texels (nothing stored between the passes).

// FxaaParams (subpix: 0 = no sub-pixel blending .. 1 = full; edge_threshold: minimum contrast relative to the
// local max luma; edge_threshold_min: absolute minimum contrast, skips dark noise) is generated from the
// effect's spec (wgpurender/core/course/effects.py) by wgpurender/wgpu_path/post/shaders.py.

const SEARCH_STEPS: u32 = 12u;

fn luma_of(c: vec3f) -> f32 {
    return sqrt(max(dot(c, LUMA_709), 0.0));
}

// The luma of texel p: fxaa_luma, generated with the reads (luma_of of fxaa_texel(p), or a workgroup tile of
// lumas filled with luma_of from the same texels on the compute path).
fn luma_at(p: vec2i) -> f32 {
    return fxaa_luma(p);
}

fn luma_uv(uv: vec2f) -> f32 {
    return luma_of(fxaa_sample(uv).rgb);
}

// Step 1: true where FXAA works on the pixel (its local contrast is high enough). Written as
// "not below" so that it is exactly the negation of the early exit's test, NaN included.
fn is_edge(l_m: f32, l_n: f32, l_s: f32, l_w: f32, l_e: f32, params: FxaaParams) -> bool {
    let l_max = max(l_m, max(max(l_n, l_s), max(l_w, l_e)));
    let l_min = min(l_m, min(min(l_n, l_s), min(l_w, l_e)));
    return !(l_max - l_min < max(params.edge_threshold_min, l_max * params.edge_threshold));
}

// Distance walked at each search step, in pixels: fine near the pixel, coarse far away.
fn search_step(i: u32) -> f32 {
    var steps = array<f32, 12>(1.0, 1.0, 1.0, 1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0);
    return steps[i];
}

// The FXAA'd colour of pixel p (pos: its centre in pixels).
fn fxaa_at(p: vec2i, pos: vec2f, params: FxaaParams) -> vec4f {
    let centre = fxaa_texel(p);
    let inv = 1.0 / vec2f(textureDimensions(src));
    let uv = pos * inv;

    // 1. local contrast (texture y grows downwards: north is -y)
    let l_m = luma_of(centre.rgb);
    let l_n = luma_at(p + vec2i(0, -1));
    let l_s = luma_at(p + vec2i(0, 1));
    let l_w = luma_at(p + vec2i(-1, 0));
    let l_e = luma_at(p + vec2i(1, 0));
    if !is_edge(l_m, l_n, l_s, l_w, l_e, params) {
        return centre;
    }
    let l_max = max(l_m, max(max(l_n, l_s), max(l_w, l_e)));
    let l_min = min(l_m, min(min(l_n, l_s), min(l_w, l_e)));
    let range = l_max - l_min;

    let l_nw = luma_at(p + vec2i(-1, -1));
    let l_ne = luma_at(p + vec2i(1, -1));
    let l_sw = luma_at(p + vec2i(-1, 1));
    let l_se = luma_at(p + vec2i(1, 1));

    // 2. sub-pixel blend amount: a smoothstep of |3x3 average - centre| / range, squared
    let average = (2.0 * (l_n + l_s + l_w + l_e) + (l_nw + l_ne + l_sw + l_se)) / 12.0;
    let sub_a = clamp(abs(average - l_m) / range, 0.0, 1.0);
    let sub_b = (3.0 - 2.0 * sub_a) * sub_a * sub_a;
    let sub_offset = sub_b * sub_b * params.subpix;

    // 3. direction. `horizontal`: the edge runs along x, luma changes along y.
    let change_y = abs(l_nw - 2.0 * l_w + l_sw) + 2.0 * abs(l_n - 2.0 * l_m + l_s) + abs(l_ne - 2.0 * l_e + l_se);
    let change_x = abs(l_nw - 2.0 * l_n + l_ne) + 2.0 * abs(l_w - 2.0 * l_m + l_e) + abs(l_sw - 2.0 * l_s + l_se);
    let horizontal = change_y >= change_x;
    let l_neg = select(l_w, l_n, horizontal);   // neighbour on the negative side across the edge
    let l_pos = select(l_e, l_s, horizontal);   // neighbour on the positive side
    let grad_neg = abs(l_neg - l_m);
    let grad_pos = abs(l_pos - l_m);
    var across = select(inv.x, inv.y, horizontal);  // one pixel across the edge, in uv
    var l_edge: f32;                                 // average luma of the two sides
    if grad_neg >= grad_pos {
        across = -across;
        l_edge = 0.5 * (l_neg + l_m);
    } else {
        l_edge = 0.5 * (l_pos + l_m);
    }
    let grad_scaled = 0.25 * max(grad_neg, grad_pos);
    let along = select(vec2f(0.0, inv.y), vec2f(inv.x, 0.0), horizontal);
    var edge_uv = uv;
    if horizontal {
        edge_uv.y += 0.5 * across;
    } else {
        edge_uv.x += 0.5 * across;
    }

    // 4. edge search in both directions
    var uv_a = edge_uv - along;
    var uv_b = edge_uv + along;
    var end_a = luma_uv(uv_a) - l_edge;
    var end_b = luma_uv(uv_b) - l_edge;
    var done_a = abs(end_a) >= grad_scaled;
    var done_b = abs(end_b) >= grad_scaled;
    for (var i = 1u; i < SEARCH_STEPS; i++) {
        if done_a && done_b {
            break;
        }
        if !done_a {
            uv_a -= along * search_step(i);
            end_a = luma_uv(uv_a) - l_edge;
            done_a = abs(end_a) >= grad_scaled;
        }
        if !done_b {
            uv_b += along * search_step(i);
            end_b = luma_uv(uv_b) - l_edge;
            done_b = abs(end_b) >= grad_scaled;
        }
    }
    let dist_a = select(uv.y - uv_a.y, uv.x - uv_a.x, horizontal);
    let dist_b = select(uv_b.y - uv.y, uv_b.x - uv.x, horizontal);
    let nearer_a = dist_a < dist_b;
    let dist = min(dist_a, dist_b);
    let edge_length = dist_a + dist_b;
    // Only shift when the nearer end really ends the edge on this pixel's side:
    // its luma must sit on the other side of the edge average than the centre.
    let centre_below = l_m < l_edge;
    let end_below = select(end_b < 0.0, end_a < 0.0, nearer_a);
    var offset = 0.0;
    if end_below != centre_below {
        offset = 0.5 - dist / edge_length;
    }
    offset = max(offset, sub_offset);

    // 5. the final, shifted bilinear fetch
    var final_uv = uv;
    if horizontal {
        final_uv.y += offset * across;
    } else {
        final_uv.x += offset * across;
    }
    let color = fxaa_sample(final_uv);
    return vec4f(color.rgb, centre.a);
}

// Draw 1 of the fragment pass (the generated fs_mark, wgpurender/wgpu_path/post/shaders.py) writes every pixel
// as fxaa_at returns it off edges, and depth 1 where this is true (fxaa_at has work to do), 0 elsewhere.
// Draw 2 (the generated fs_main, the triangle at depth 0, compare "less") then runs only on edge pixels.
fn fxaa_marks(p: vec2i, params: FxaaParams) -> bool {
    let centre = fxaa_texel(p);
    return is_edge(luma_of(centre.rgb), luma_at(p + vec2i(0, -1)), luma_at(p + vec2i(0, 1)),
                   luma_at(p + vec2i(-1, 0)), luma_at(p + vec2i(1, 0)), params);
}


// Vignette: darken towards the corners, see wgpurender/core/course/effects.py (the spec).
// Needs post_common.wgsl (prepended).
//
// d = distance from the image centre in uv units, scaled so a corner is 1;
// factor = 1 - strength * smoothstep(radius, radius + softness, d).

// VignetteParams is generated from the effect's spec (wgpurender/wgpu_path/post/shaders.py).

fn vignette_pixel(texel: vec4f, pos: vec2f, size: vec2f, params: VignetteParams) -> vec4f {
    let uv = pos / size;
    let d = length(uv - vec2f(0.5)) * sqrt(2.0);
    let factor = 1.0 - params.strength * smoothstep(params.radius, params.radius + params.softness, d);
    return vec4f(texel.rgb * factor, texel.a);
}


// Output encoding: linear -> sRGB (IEC 61966-2-1), see wgpurender/core/course/effects.py (the sRGB rule).
// Needs post_common.wgsl (prepended).
//
// SRGB_ENCODE is set per target format when the pipeline is made: 1 for plain 8-bit
// unorm targets (the shader must encode), 0 for -srgb targets (the hardware
// encodes on write; encoding here too would encode twice) and for float targets
// (which hold linear values by this project's rule).
override SRGB_ENCODE: f32 = 0.0;

fn srgb_encode(linear: vec3f) -> vec3f {
    let x = clamp(linear, vec3f(0.0), vec3f(1.0));
    let lo = 12.92 * x;
    let hi = 1.055 * pow(x, vec3f(1.0 / 2.4)) - 0.055;
    return select(hi, lo, x <= vec3f(0.0031308));
}

fn srgb_pixel(texel: vec4f, pos: vec2f, size: vec2f) -> vec4f {
    if SRGB_ENCODE > 0.5 {
        return vec4f(srgb_encode(texel.rgb), texel.a);
    }
    return texel;
}



fn tile_source(p: vec2i) -> vec4f {
    return src_clamped(p);
}

fn fxaa_texel(p: vec2i) -> vec4f {
    return tile_source(p);
}

fn fxaa_luma(p: vec2i) -> f32 {
    return luma_of(fxaa_texel(p).rgb);
}

fn fxaa_sample(uv: vec2f) -> vec4f {
    return textureSampleLevel(src, src_sampler, uv, 0.0);
}


fn pass_tail(c0: vec4f, pos: vec2f, size: vec2f) -> vec4f {
    var c = c0;
    c = vignette_pixel(c, pos, size, params.s1);
    c = vec4f(srgb_encode(c.rgb), c.a);
    return c;
}

fn pass_color(p: vec2i, pos: vec2f, size: vec2f) -> vec4f {
    return pass_tail(fxaa_at(p, pos, params.s0), pos, size);
}


@group(0) @binding(3) var dst: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let size = textureDimensions(src);
    for (var k = 0u; k < 2u; k++) {
        let xy = vec2u(id.x, id.y * 2u + k);  // 2 rows per invocation, neighbours in x stay neighbours
        if xy.x < size.x && xy.y < size.y {
            let p = vec2i(xy);
            textureStore(dst, p, pass_color(p, vec2f(xy) + vec2f(0.5), vec2f(size)));
        }
    }
}

