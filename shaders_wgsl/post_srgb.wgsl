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
