// Course step 3c, the wgpu side of the raw msaa-post stage (shaders_glsl/post_grayscale.frag):
// the second pass's full-screen triangle reads the resolved MSAA image and mixes it towards its
// Rec. 709 luminance (linear values: an -srgb texture decodes on read, the target encodes on write).
//
// Raw Vulkan reads the resolve as an INPUT ATTACHMENT in subpass 1 of the same render pass
// (subpassLoad: this pixel only). WebGPU has no subpasses or input attachments (it maps onto
// Metal and D3D12, which expose none; gfx-rs/wgpu#10148 is open), so here the resolve is an
// ordinary sampled texture read with textureLoad in a render pass of its own.

@group(0) @binding(0) var scene: texture_2d<f32>;

struct Post {
    amount: f32,  // 0: unchanged, 1: fully grey (a push constant on the raw path)
};
@group(0) @binding(1) var<uniform> post: Post;

struct FullscreenOut {
    @builtin(position) position: vec4f,
};

// One triangle that covers the viewport: NDC (-1,-1), (3,-1), (-1,3) (shaders_glsl/fullscreen.vert).
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> FullscreenOut {
    let x = f32((index << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(index & 2u) * 2.0 - 1.0;
    var out: FullscreenOut;
    out.position = vec4f(x, y, 0.0, 1.0);
    return out;
}

@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4f {
    let color = textureLoad(scene, vec2i(in.position.xy), 0).rgb;
    let luma = dot(color, vec3f(0.2126, 0.7152, 0.0722));
    return vec4f(mix(color, vec3f(luma), post.amount), 1.0);
}
