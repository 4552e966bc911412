#version 450
// Post effect of the msaa-post stage: reads the resolved scene of subpass 0 as an input
// attachment (only the current pixel can be read: subpassLoad takes no coordinates) and
// mixes it towards its luminance. Rec. 709 weights, applied to linear values: with an
// -srgb attachment, subpassLoad decodes to linear and the output write encodes again.

layout(input_attachment_index = 0, set = 0, binding = 0) uniform subpassInput scene;

layout(push_constant) uniform Post {
    float amount;  // 0: unchanged, 1: fully grey
} post;

layout(location = 0) out vec4 out_color;

void main() {
    vec3 color = subpassLoad(scene).rgb;
    float luma = dot(color, vec3(0.2126, 0.7152, 0.0722));
    out_color = vec4(mix(color, vec3(luma), post.amount), 1.0);
}
