// Vignette: darken towards the corners, see wgpurender/post/vignette.py.
// Needs post_common.wgsl (prepended).
//
// d = distance from the image centre in uv units, scaled so a corner is 1;
// factor = 1 - strength * smoothstep(radius, radius + softness, d).

struct Params {
    strength: f32,
    radius: f32,
    softness: f32,
};
@group(0) @binding(2) var<uniform> params: Params;

@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4f {
    let texel = src_texel(in.position);
    let uv = in.position.xy / vec2f(textureDimensions(src));
    let d = length(uv - vec2f(0.5)) * sqrt(2.0);
    let factor = 1.0 - params.strength * smoothstep(params.radius, params.radius + params.softness, d);
    return vec4f(texel.rgb * factor, texel.a);
}
