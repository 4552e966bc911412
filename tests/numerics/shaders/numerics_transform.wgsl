// Hard-case probe (tests/numerics/gpu_eval.py): clip = second * (first * p) in float32,
// as a vertex shader would compute it from two uniform matrices. Which matrices are passed
// decides naive (world, proj*view) or camera-relative (view*world composed in float64, proj).

@group(0) @binding(0) var<storage, read> positions: array<vec4f>;
@group(0) @binding(1) var<storage, read> matrices: array<mat4x4f, 2>;
@group(0) @binding(2) var<storage, read_write> out: array<vec4f>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let i = id.x;
    if i >= arrayLength(&positions) {
        return;
    }
    let p = matrices[0] * positions[i];
    out[i] = matrices[1] * p;
}
