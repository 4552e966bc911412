// Course step 2a: the first triangle with no vertex buffer at all.
// Position and colour come from the vertex index, like gl_VertexIndex in the
// Vulkan tutorial's first shader. The values match TRIANGLE_* in
// wgpurender/wgpu_path/stages/triangle.py; a test checks both variants draw the same image.

struct VertexOut {
    @builtin(position) position: vec4f,
    @location(0) color: vec3f,
};

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VertexOut {
    var positions = array<vec2f, 3>(vec2f(-0.8, -0.7), vec2f(0.7, -0.5), vec2f(-0.1, 0.8));
    var colors = array<vec3f, 3>(vec3f(1.0, 0.0, 0.0), vec3f(0.0, 1.0, 0.0), vec3f(0.0, 0.0, 1.0));
    var out: VertexOut;
    out.position = vec4f(positions[index], 0.0, 1.0);
    out.color = colors[index];
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4f {
    return vec4f(in.color, 1.0);
}
