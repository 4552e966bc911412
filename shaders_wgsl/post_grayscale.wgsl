// Grayscale: Rec. 709 luma of linear RGB, mixed in by `amount`, see wgpurender/core/course/effects.py (the spec).
// Needs post_common.wgsl (prepended).

// GrayscaleParams is generated from the effect's spec (wgpurender/wgpu_path/post/shaders.py).

fn grayscale_pixel(texel: vec4f, pos: vec2f, size: vec2f, params: GrayscaleParams) -> vec4f {
    let y = dot(texel.rgb, LUMA_709);
    return vec4f(mix(texel.rgb, vec3f(y), params.amount), texel.a);
}
