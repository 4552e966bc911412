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
