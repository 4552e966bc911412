// Output encoding: linear -> sRGB (IEC 61966-2-1), see wgpurender/post/srgb.py.
// Needs post_common.wgsl (prepended).
//
// ENCODE is set per target format when the pipeline is made: 1 for plain 8-bit
// unorm targets (the shader must encode), 0 for -srgb targets (the hardware
// encodes on write; encoding here too would encode twice) and for float targets
// (which hold linear values by this project's rule).
@id(0) override ENCODE: f32 = 0.0;

fn srgb_encode(linear: vec3f) -> vec3f {
    let x = clamp(linear, vec3f(0.0), vec3f(1.0));
    let lo = 12.92 * x;
    let hi = 1.055 * pow(x, vec3f(1.0 / 2.4)) - 0.055;
    return select(hi, lo, x <= vec3f(0.0031308));
}

@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4f {
    let texel = src_texel(in.position);
    if ENCODE > 0.5 {
        return vec4f(srgb_encode(texel.rgb), texel.a);
    }
    return texel;
}
