// Post-pass probe (wgpurender/bench/post.py): the cheapest possible full-screen pass, a copy,
// with one knob per suspect cost. Variant flags:
//   sampler   read through a linear sampler at the pixel centre (else textureLoad);
//   quad      two triangles from six vertices (else one oversized triangle).

@group(0) @binding(0) var src: texture_2d<f32>;
#if sampler
@group(0) @binding(1) var smp: sampler;
#endif

struct VsOut {
    @builtin(position) position: vec4f,
};

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VsOut {
#if quad
    // (-1,-1) (1,-1) (-1,1) | (-1,1) (1,-1) (1,1)
    let k = array<u32, 6>(0u, 1u, 2u, 2u, 1u, 3u)[index];
    let p = vec2f(f32(k & 1u) * 2.0 - 1.0, f32((k >> 1u) & 1u) * 2.0 - 1.0);
#else
    let p = vec2f(f32((index << 1u) & 2u) * 2.0 - 1.0, f32(index & 2u) * 2.0 - 1.0);
#endif
    var out: VsOut;
    out.position = vec4f(p, 0.0, 1.0);
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4f {
#if sampler
    let uv = in.position.xy / vec2f(textureDimensions(src));
    return textureSampleLevel(src, smp, uv, 0.0);
#else
    return textureLoad(src, vec2i(in.position.xy), 0);
#endif
}
