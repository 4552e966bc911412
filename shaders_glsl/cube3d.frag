#version 450
// Lambert + ambient with flat face colours (as shaders_wgsl/cube3d.wgsl).

layout(std140, set = 0, binding = 0) uniform Camera {
    mat4 proj;
    mat4 view;
    vec3 light_dir;
    float ambient;
} camera;

layout(location = 0) in vec3 v_normal;
layout(location = 1) in vec3 v_color;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 n = normalize(v_normal);
    float lambert = max(dot(n, camera.light_dir), 0.0);
    float light = camera.ambient + (1.0 - camera.ambient) * lambert;
    out_color = vec4(v_color * light, 1.0);
}
