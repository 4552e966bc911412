// Course step 5: a textured quad, two ways of binding the texture and its sampler.
//
// fs_combined: texture and sampler in one bind group (group 1), the analogue of a
//   VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER / GLSL sampler2D. WGSL has no combined
//   type, so "combined" means: always bound together, as one descriptor set.
// fs_separate: the texture alone in group 1 and the sampler alone in group 2, the
//   analogue of VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE + VK_DESCRIPTOR_TYPE_SAMPLER
//   (GLSL texture2D + sampler). The texture group stays bound; only the small
//   sampler group changes between draws.
//
// Vertex layout (wgpurender/wgpu_path/stages/textured.py VERTEX_LAYOUT): float32x3 position
// at 0, float32x2 uv at 12, stride 20. uv (0,0) is the first texel row's left edge.

struct Uniforms {
    mvp: mat4x4f,
    uv_offset: vec4f,  // xy: added to uv (scrolls the texture with t); zw unused
};

@group(0) @binding(0) var<uniform> u: Uniforms;

@group(1) @binding(0) var color_texture: texture_2d<f32>;
@group(1) @binding(1) var combined_sampler: sampler;

@group(2) @binding(0) var separate_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3f,
    @location(1) uv: vec2f,
};

struct VertexOut {
    @builtin(position) position: vec4f,
    @location(0) uv: vec2f,
};

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.position = u.mvp * vec4f(in.position, 1.0);
    out.uv = in.uv + u.uv_offset.xy;
    return out;
}

@fragment
fn fs_combined(in: VertexOut) -> @location(0) vec4f {
    return textureSample(color_texture, combined_sampler, in.uv);
}

@fragment
fn fs_separate(in: VertexOut) -> @location(0) vec4f {
    return textureSample(color_texture, separate_sampler, in.uv);
}
