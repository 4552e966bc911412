#version 450
// Sharpen on the raw path: shaders_wgsl/post_sharpen.wgsl's 3x3 Laplacian (centre 1 + 4k, the four edge
// neighbours -k, clamp-to-edge at the borders, result clamped at 0), operation for operation.
// It reads four neighbours, which an input attachment cannot give (subpassLoad reads only the pixel
// under the fragment): the previous result is a sampled image in a render pass of its own
// (wgpurender/raw_path/post/neighbourhood.py); the strength is a push constant.

layout(set = 0, binding = 0) uniform sampler2D src;

layout(push_constant) uniform Params {
    float strength;
} params;

layout(location = 0) out vec4 out_color;

vec4 src_clamped(ivec2 p) {
    ivec2 last = textureSize(src, 0) - ivec2(1, 1);
    return texelFetch(src, clamp(p, ivec2(0, 0), last), 0);
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = src_clamped(p);
    vec3 n = src_clamped(p + ivec2(0, -1)).rgb;
    vec3 s = src_clamped(p + ivec2(0, 1)).rgb;
    vec3 w = src_clamped(p + ivec2(-1, 0)).rgb;
    vec3 e = src_clamped(p + ivec2(1, 0)).rgb;
    float k = params.strength;
    vec3 sharp = c.rgb * (1.0 + 4.0 * k) - k * (n + s + w + e);
    out_color = vec4(max(sharp, vec3(0.0)), c.a);
}
