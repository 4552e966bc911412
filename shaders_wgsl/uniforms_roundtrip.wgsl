// Uniform layout self-check: read every scalar of a uniform struct and write its bits out.
//
// Used by wgpurender/uniforms.py:roundtrip_wgsl() (and tests/test_uniforms.py). The Python
// side puts the generated struct declarations in front of this text and replaces the two
// markers below (STRUCT and COPIES in double braces; the comments must not spell them):
//   STRUCT  the name of the struct under test;
//   COPIES  one statement per scalar, in declaration order:
//               out_words[i] = bitcast<u32>(u.<path to the scalar>);
// If the Python packer and WGSL disagree about any offset, padding or matrix orientation,
// the words read back differ from the values that were packed.

@group(0) @binding(0) var<uniform> u: {{STRUCT}};
@group(0) @binding(1) var<storage, read_write> out_words: array<u32>;

@compute @workgroup_size(1)
fn main() {
    {{COPIES}}
}
