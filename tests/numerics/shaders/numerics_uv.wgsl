// UV-precision probe (tests/numerics/uv_tiling.py): a quad with the given UVs; each pixel
// writes its interpolated texel coordinate fract(uv) * size (.xy) and the texel the sampler
// fetched with nearest filtering and repeat addressing (.zw: the texture stores its own indices).

@group(0) @binding(0) var index_texture: texture_2d<f32>;
@group(0) @binding(1) var nearest_repeat: sampler;

struct VsOut {
    @builtin(position) position: vec4f,
    @location(0) uv: vec2f,
};

@vertex
fn vs_main(@location(0) ndc: vec2f, @location(1) uv: vec2f) -> VsOut {
    var out: VsOut;
    out.position = vec4f(ndc, 0.0, 1.0);
    out.uv = uv;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4f {
    let size = vec2f(textureDimensions(index_texture));
    let fetched = textureSampleLevel(index_texture, nearest_repeat, in.uv, 0.0);
    return vec4f(fract(in.uv) * size, fetched.xy);
}
