// Uniform layout self-check: read every scalar of a uniform struct and write its bits out.
//
// Filled in by wgpurender/core/shaders/uniforms.py:roundtrip_wgsl() with shader_variants.specialise():
//   STRUCTS  the struct declarations generated from the Python definition;
//   STRUCT   the name of the struct under test;
//   COPIES   one statement per scalar, in declaration order:
//            out_words[i] = bitcast<u32>(u.<path to the scalar>);
// (each written in double braces where it is used below). If the Python packer and WGSL
// disagree about an offset, padding or matrix orientation, the words read back differ from
// the values that were packed. Used by tests/test_uniforms.py.

{{STRUCTS}}

@group(0) @binding(0) var<uniform> u: {{STRUCT}};
@group(0) @binding(1) var<storage, read_write> out_words: array<u32>;

@compute @workgroup_size(1)
fn main() {
    {{COPIES}}
}
