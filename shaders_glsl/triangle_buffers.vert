#version 450
// Course step 2b: the triangle's vertices from a vertex buffer. The input layout
// (binding 0, stride 20; location 0 vec2 at offset 0, location 1 vec3 at offset 8)
// is declared in wgpurender/raw_path/stages/triangle_buffers.py.

layout(location = 0) in vec2 a_position;
layout(location = 1) in vec3 a_color;
layout(location = 0) out vec3 v_color;

void main() {
    gl_Position = vec4(a_position, 0.0, 1.0);
    v_color = a_color;
}
