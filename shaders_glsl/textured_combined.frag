#version 450
// Course step 5, left half: a COMBINED_IMAGE_SAMPLER descriptor: image and sampler in one
// descriptor, a GLSL sampler2D. (wgpu cannot take this form: its left half binds the texture
// and the sampler as two entries of one bind group instead.)

layout(set = 1, binding = 0) uniform sampler2D color_texture;

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = texture(color_texture, v_uv);
}
