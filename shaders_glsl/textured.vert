#version 450
// Course step 5: the textured plane. The same computation as vs_main in shaders_wgsl/textured.wgsl;
// the std140 block is packed by hand in wgpurender/raw_path/stages/textured.py (mvp @0, uv_offset @64).

layout(std140, set = 0, binding = 0) uniform Uniforms {
    mat4 mvp;
    vec4 uv_offset;  // xy: added to uv (scrolls the texture with t); zw unused
} u;

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec2 a_uv;
layout(location = 0) out vec2 v_uv;

void main() {
    gl_Position = u.mvp * vec4(a_position, 1.0);
    v_uv = a_uv + u.uv_offset.xy;
}
