// Tone mapping: linear HDR (rgba16float) -> linear [0, 1], see wgpurender/core/course/effects.py (the spec).
// Needs post_common.wgsl (prepended).

// TonemapParams (exposure, operator_index: 0 = ACES fitted (Hill), 1 = Reinhard) is generated from the
// effect's spec (wgpurender/core/course/effects.py) by wgpurender/wgpu_path/post/shaders.py.

// ACES fitted (Stephen Hill's fit of the ACES RRT + sRGB ODT): input matrix
// (sRGB -> ACES-ish space, with the RRT saturation folded in), a rational curve,
// output matrix back to sRGB primaries. Matrices are written row by row; WGSL
// mat3x3f takes columns, so rows are applied with dot products.
fn aces_fitted(c: vec3f) -> vec3f {
    let a = vec3f(dot(vec3f(0.59719, 0.35458, 0.04823), c),
                  dot(vec3f(0.07600, 0.90834, 0.01566), c),
                  dot(vec3f(0.02840, 0.13383, 0.83777), c));
    let b = (a * (a + 0.0245786) - 0.000090537) / (a * (0.983729 * a + 0.4329510) + 0.238081);
    let o = vec3f(dot(vec3f(1.60475, -0.53108, -0.07367), b),
                  dot(vec3f(-0.10208, 1.10813, -0.00605), b),
                  dot(vec3f(-0.00327, -0.07276, 1.07602), b));
    return clamp(o, vec3f(0.0), vec3f(1.0));
}

fn reinhard(c: vec3f) -> vec3f {
    return c / (1.0 + c);
}

fn tonemap_pixel(texel: vec4f, pos: vec2f, size: vec2f, params: TonemapParams) -> vec4f {
    // Clamp to the largest finite f16 before and after exposure: both curves are flat there (ACES at 1,
    // Reinhard at 0.99998), while inf (or a * a past 1.8e19 inside ACES) would give inf / inf = NaN.
    let hdr = min(max(texel.rgb, vec3f(0.0)), vec3f(65504.0));
    let c = min(hdr * params.exposure, vec3f(65504.0));
    var mapped: vec3f;
    if params.operator_index < 0.5 {
        mapped = aces_fitted(c);
    } else {
        mapped = reinhard(c);
    }
    return vec4f(mapped, texel.a);
}
