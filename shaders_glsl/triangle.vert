#version 450
// Course step 2a: the first triangle with no vertex buffer; position and colour from gl_VertexIndex.
// Same numbers as shaders_wgsl/triangle.wgsl: NDC with y UP (wgpu's convention). The raw-Vulkan
// path flips its viewport (negative height) so that y up here lands at the top of the image.

layout(location = 0) out vec3 v_color;

const vec2 POSITIONS[3] = vec2[](vec2(-0.8, -0.7), vec2(0.7, -0.5), vec2(-0.1, 0.8));
const vec3 COLORS[3] = vec3[](vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0));

void main() {
    gl_Position = vec4(POSITIONS[gl_VertexIndex], 0.0, 1.0);
    v_color = COLORS[gl_VertexIndex];
}
