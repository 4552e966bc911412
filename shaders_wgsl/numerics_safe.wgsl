// Guarded vector normalisation for the hard-case shaders (prepended to numerics_normals.wgsl and
// numerics_lit.wgsl by wgpurender/numerics; see docs/numerics.md).
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
    let u = v / m;
    return u * inverseSqrt(dot(u, u));
}
