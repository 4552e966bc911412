// Coverage probe (tests/numerics/coverage.py): flat white triangles from NDC positions.
// Resolved MSAA value of a pixel = covered samples / sample count.

@vertex
fn vs_main(@location(0) ndc: vec2f) -> @builtin(position) vec4f {
    return vec4f(ndc, 0.0, 1.0);
}

@fragment
fn fs_main() -> @location(0) vec4f {
    return vec4f(1.0, 1.0, 1.0, 1.0);
}
