#version 450
// Course step 4: cubes with two UBOs in two descriptor sets and per-draw push constants.
// The same computation as shaders_wgsl/cube3d.wgsl; the std140 offsets are spelled out in
// wgpurender/raw_path/device/ubo.py.

layout(std140, set = 0, binding = 0) uniform Camera {
    mat4 proj;
    mat4 view;
    vec3 light_dir;
    float ambient;
} camera;

// One buffer holds every cube's block; a dynamic offset picks one per draw.
layout(std140, set = 1, binding = 0) uniform ObjectData {
    mat4 world;
    mat3 normal;
} object_data;

layout(push_constant) uniform Draw {
    vec4 tint;
    uint object_index;
} draw;

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
layout(location = 0) out vec3 v_normal;
layout(location = 1) out vec3 v_color;

vec3 permute_channels(vec3 c, uint k) {
    uint r = k % 3u;
    return r == 1u ? c.gbr : (r == 2u ? c.brg : c);
}

void main() {
    vec4 world = object_data.world * vec4(a_position, 1.0);
    gl_Position = camera.proj * camera.view * world;
    v_normal = object_data.normal * a_normal;
    v_color = permute_channels(a_color, draw.object_index) * draw.tint.rgb;
}
