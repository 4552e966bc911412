// Normal-transform probe (tests/numerics/gpu_eval.py), after numerics_safe.wgsl.
// matrices[0] is the world matrix, matrices[1] the normal matrix from the CPU (upper-left 3x3 used).
// MODE 0: ours, the CPU's (scaled) cofactor normal matrix + safe_normalize;
// MODE 1: naive, inverse-transpose computed here in f32 (cofactor / determinant) + normalize;
// MODE 2: naive, the world matrix itself + normalize (wrong under non-uniform scale).

override MODE: u32 = 0u;

@group(0) @binding(0) var<storage, read> normals: array<vec4f>;
@group(0) @binding(1) var<storage, read> matrices: array<mat4x4f, 2>;
@group(0) @binding(2) var<storage, read_write> out: array<vec4f>;

fn upper3(m: mat4x4f) -> mat3x3f {
    return mat3x3f(m[0].xyz, m[1].xyz, m[2].xyz);
}

// transpose(inverse(m)) = cofactor(m) / det(m); the cofactor matrix's columns are cross products of m's columns.
fn naive_inverse_transpose(m: mat3x3f) -> mat3x3f {
    let cof = mat3x3f(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
    let det = determinant(m);
    return cof * (1.0 / det);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let i = id.x;
    if i >= arrayLength(&normals) {
        return;
    }
    let n = normals[i].xyz;
    var r: vec3f;
    if MODE == 0u {
        r = safe_normalize(upper3(matrices[1]) * n, vec3f(0.0, 0.0, 1.0));
    } else if MODE == 1u {
        r = normalize(naive_inverse_transpose(upper3(matrices[0])) * n);
    } else {
        r = normalize(upper3(matrices[0]) * n);
    }
    out[i] = vec4f(r, 0.0);
}
