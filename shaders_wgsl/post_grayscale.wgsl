// Grayscale: Rec. 709 luma of linear RGB, mixed in by `amount`, see wgpurender/post/grayscale.py.
// Needs post_common.wgsl (prepended).

struct Params {
    amount: f32,
};
@group(0) @binding(2) var<uniform> params: Params;

@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4f {
    let texel = src_texel(in.position);
    let y = dot(texel.rgb, LUMA_709);
    return vec4f(mix(texel.rgb, vec3f(y), params.amount), texel.a);
}
