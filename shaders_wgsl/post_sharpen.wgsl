// Sharpen: 3x3 Laplacian kernel (centre 1 + 4k, the four edge neighbours -k),
// clamp-to-edge at the borders, result clamped at 0. See wgpurender/core/course/effects.py.
// Needs post_common.wgsl (prepended).

// SharpenParams is generated from the effect's spec (wgpurender/wgpu_path/post/shaders.py).

fn sharpen_at(p: vec2i, pos: vec2f, params: SharpenParams) -> vec4f {
    let c = src_clamped(p);
    let n = src_clamped(p + vec2i(0, -1)).rgb;
    let s = src_clamped(p + vec2i(0, 1)).rgb;
    let w = src_clamped(p + vec2i(-1, 0)).rgb;
    let e = src_clamped(p + vec2i(1, 0)).rgb;
    let k = params.strength;
    let sharp = c.rgb * (1.0 + 4.0 * k) - k * (n + s + w + e);
    return vec4f(max(sharp, vec3f(0.0)), c.a);
}
