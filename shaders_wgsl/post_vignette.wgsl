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
