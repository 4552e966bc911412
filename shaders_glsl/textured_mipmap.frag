#version 450
// Course step 5: one mip level from the previous one, drawn by a render pass per level
// (wgpurender/raw_path/device/textures.py). The same arithmetic as shaders_wgsl/mipmap.wgsl, in the
// same order, so that both paths build bit-identical mip chains:
// an exact area-weighted box filter in integers. Along one axis, source texel i covers
// [i*dst, (i+1)*dst) and destination texel x covers [x*src, (x+1)*src) in units of
// 1/(src*dst); a destination texel overlaps at most 3 source texels, each weighted
// overlap / src. texelFetch of an -srgb image returns linear values and the -srgb
// attachment encodes again, so the average is taken in linear light.
//
// The course uses vkCmdBlitImage with VK_FILTER_LINEAR here instead: a different filter
// (bilinear resampling by the driver), so the two paths could not be compared exactly.

#extension GL_EXT_samplerless_texture_functions : require

layout(set = 0, binding = 0) uniform texture2D src;  // a one-level view of level i-1 (SAMPLED_IMAGE)
layout(location = 0) out vec4 out_color;

void axis_taps(uint x, uint src_size, uint dst_size, out uint first, out vec3 weights) {
    uint lo = x * src_size;
    uint hi = lo + src_size;
    first = lo / dst_size;
    for (uint k = 0u; k < 3u; k++) {
        uint i = first + k;
        uint a = max(i * dst_size, lo);
        uint b = min((i + 1u) * dst_size, hi);
        weights[k] = (b > a ? float(b - a) : 0.0) / float(src_size);
    }
}

void main() {
    uvec2 src_size = uvec2(textureSize(src, 0));
    uvec2 dst_size = max(src_size >> 1u, uvec2(1u));
    uvec2 dst = uvec2(gl_FragCoord.xy);
    uint first_x, first_y;
    vec3 wx, wy;
    axis_taps(dst.x, src_size.x, dst_size.x, first_x, wx);
    axis_taps(dst.y, src_size.y, dst_size.y, first_y, wy);
    vec4 sum = vec4(0.0);
    for (uint j = 0u; j < 3u; j++) {
        for (uint i = 0u; i < 3u; i++) {
            float w = wx[i] * wy[j];
            uvec2 coord = min(uvec2(first_x + i, first_y + j), src_size - uvec2(1u));
            sum += w * texelFetch(src, ivec2(coord), 0);
        }
    }
    out_color = sum;
}
