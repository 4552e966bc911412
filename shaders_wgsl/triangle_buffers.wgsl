// Course step 2b: the same triangle, its vertices read from a vertex buffer
// through an explicit vertex layout (the Vulkan input layout:
// VkVertexInputBindingDescription + VkVertexInputAttributeDescription).

struct VertexIn {
    @location(0) position: vec2f,
    @location(1) color: vec3f,
};

struct VertexOut {
    @builtin(position) position: vec4f,
    @location(0) color: vec3f,
};

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.position = vec4f(in.position, 0.0, 1.0);
    out.color = in.color;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4f {
    return vec4f(in.color, 1.0);
}
