#version 450
// Course step 5, right half: a SAMPLED_IMAGE descriptor (set 1, bound once) and a SAMPLER
// descriptor (set 2, one per lane), combined in the shader by the sampler2D constructor.

layout(set = 1, binding = 0) uniform texture2D color_texture;
layout(set = 2, binding = 0) uniform sampler lane_sampler;

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = texture(sampler2D(color_texture, lane_sampler), v_uv);
}
