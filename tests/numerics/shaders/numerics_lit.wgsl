// Lit, normal-mapped surface for the degenerate-geometry and scale hard cases
// (tests/numerics/lit.py), after numerics_safe.wgsl. Writes linear radiance to a float target,
// so a NaN or inf computed here reaches the image instead of being clamped away by a unorm format.
// SAFE = true: every normalisation goes through safe_normalize; false: plain normalize (counter-example).

override SAFE: bool = true;

struct Uniforms {
    clip_from_model: mat4x4f,
    normal_matrix: mat4x4f,  // upper-left 3x3 used: the CPU's cofactor normal matrix
    light_dir: vec4f,        // xyz: unit direction towards the light
};
@group(0) @binding(0) var<uniform> u: Uniforms;

struct VsIn {
    @location(0) position: vec3f,
    @location(1) normal: vec3f,
    @location(2) tangent: vec4f,
    @location(3) uv: vec2f,
};

struct VsOut {
    @builtin(position) position: vec4f,
    @location(0) normal: vec3f,
    @location(1) tangent: vec4f,
    @location(2) uv: vec2f,
};

fn nrm(v: vec3f, fallback: vec3f) -> vec3f {
    if SAFE {
        return safe_normalize(v, fallback);
    }
    return normalize(v);
}

@vertex
fn vs_main(in: VsIn) -> VsOut {
    let n3 = mat3x3f(u.normal_matrix[0].xyz, u.normal_matrix[1].xyz, u.normal_matrix[2].xyz);
    var out: VsOut;
    out.position = u.clip_from_model * vec4f(in.position, 1.0);
    out.normal = n3 * in.normal;  // normalised per fragment
    out.tangent = vec4f(n3 * in.tangent.xyz, in.tangent.w);  // fine for the direction tests here
    out.uv = in.uv;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4f {
    let n = nrm(in.normal, vec3f(0.0, 0.0, 1.0));
    // Gram-Schmidt against n; a tangent parallel to n (or zero) has no direction left
    let t = nrm(in.tangent.xyz - n * dot(n, in.tangent.xyz), vec3f(1.0, 0.0, 0.0));
    let b = cross(n, t) * select(1.0, -1.0, in.tangent.w < 0.0);
    // a procedural tangent-space normal map (bumps along u and v)
    let m = vec3f(0.3 * sin(6.2831853 * in.uv.x), 0.3 * cos(6.2831853 * in.uv.y), 1.0);
    let shading_n = nrm(t * m.x + b * m.y + n * m.z, n);
    // half-Lambert ("wrap") diffuse, 0.5 + 0.5 n.l: no max() that could swallow a NaN (max(NaN, 0) gives 0
    // on many GPUs, which would hide the problem rather than fix it)
    let diffuse = 0.5 + 0.5 * dot(shading_n, u.light_dir.xyz);
    let albedo = vec3f(0.5 + 0.5 * fract(in.uv.x), 0.6, 0.5 + 0.5 * fract(in.uv.y));
    return vec4f(albedo * (0.1 + 0.9 * diffuse), 1.0);
}
