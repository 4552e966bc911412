// Guarded vector normalisation for the hard-case shaders (prepended to numerics_normals.wgsl and
// numerics_lit.wgsl by tests/numerics; see docs/numerics.md).
//
// normalize(v) is v * inverseSqrt(dot(v, v)): for v = 0 that is 0 * inf = NaN, and for a tiny v
// (|v| < 1e-19) dot(v, v) underflows to 0 with the same result, although v has a direction.
// safe_normalize divides by the largest component first (exact, keeps the direction), so the
// dot product is between 1 and 3, and returns `fallback` only when v is exactly zero or not finite.

fn safe_normalize(v: vec3f, fallback: vec3f) -> vec3f {
    let m = max(abs(v.x), max(abs(v.y), abs(v.z)));
    // m > 0 is false for NaN; m < inf rejects inf (3.4e38 is the largest finite f32)
    if !(m > 0.0) || !(m <= 3.4028235e38) {
        return fallback;
    }
    // Bring m near 1 with an exact power-of-two scale before dividing. Dividing by m directly
    // fails for m > 2^126 on GPUs that compile v / m as v * (1 / m) and flush the denormal
    // reciprocal to zero (seen on NVIDIA's Vulkan driver: (3e38, 3e38, 0) came out NaN).
    var w = v;
    var s = m;
    if m > 1.0e30 {
        w = v * 5.421010862427522e-20;  // 2^-64
        s = m * 5.421010862427522e-20;
    } else if m < 1.0e-30 {
        w = v * 1.8446744073709552e19;  // 2^64
        s = m * 1.8446744073709552e19;
    }
    let u = w / s;
    return u * inverseSqrt(dot(u, u));
}
