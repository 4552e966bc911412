#version 450
// FXAA on the raw path: the algorithm of shaders_wgsl/post_fxaa.wgsl (FXAA 3.11-style, quality),
// operation for operation, so that both paths compute the same image (tests/test_vulkan_ref_neighbourhood.py).
// Read the WGSL file for the steps; only the API differs:
//
// - the previous result is a COMBINED_IMAGE_SAMPLER (set 0, binding 0: linear filter, clamp to edge),
//   not an input attachment: FXAA samples neighbours and between pixels, which subpassLoad cannot
//   (it reads only the pixel under the fragment). So FXAA runs in a render pass of its own, after a
//   barrier that makes the previous pass's colour writes visible to this fragment shader
//   (wgpurender/raw_path/post/neighbourhood.py);
// - the parameters are push constants (12 bytes), not a uniform buffer;
// - one draw: the wgpu path's mark-then-FXAA pair of draws (a speed-up for llvmpipe) gives the
//   same pixels as this single draw (wgpurender/wgpu_path/post/passes.py).

layout(set = 0, binding = 0) uniform sampler2D src;

layout(push_constant) uniform Params {
    float subpix;              // 0 = no sub-pixel blending, 1 = full (0.75 is FXAA's default)
    float edge_threshold;      // minimum contrast relative to the local max luma (0.166)
    float edge_threshold_min;  // absolute minimum contrast, skips dark noise (0.0833)
} params;

layout(location = 0) out vec4 out_color;

const vec3 LUMA_709 = vec3(0.2126, 0.7152, 0.0722);
const uint SEARCH_STEPS = 12u;
const float STEPS[12] = float[12](1.0, 1.0, 1.0, 1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0);

vec4 src_clamped(ivec2 p) {
    ivec2 last = textureSize(src, 0) - ivec2(1, 1);
    return texelFetch(src, clamp(p, ivec2(0, 0), last), 0);
}

float luma_of(vec3 c) {
    return sqrt(max(dot(c, LUMA_709), 0.0));
}

float luma_at(ivec2 p) {
    return luma_of(src_clamped(p).rgb);
}

float luma_uv(vec2 uv) {
    return luma_of(textureLod(src, uv, 0.0).rgb);
}

bool is_edge(float l_m, float l_n, float l_s, float l_w, float l_e) {
    float l_max = max(l_m, max(max(l_n, l_s), max(l_w, l_e)));
    float l_min = min(l_m, min(min(l_n, l_s), min(l_w, l_e)));
    return !(l_max - l_min < max(params.edge_threshold_min, l_max * params.edge_threshold));
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 centre = src_clamped(p);
    vec2 inv = 1.0 / vec2(textureSize(src, 0));
    vec2 uv = gl_FragCoord.xy * inv;

    // 1. local contrast (image y grows downwards: north is -y)
    float l_m = luma_of(centre.rgb);
    float l_n = luma_at(p + ivec2(0, -1));
    float l_s = luma_at(p + ivec2(0, 1));
    float l_w = luma_at(p + ivec2(-1, 0));
    float l_e = luma_at(p + ivec2(1, 0));
    if (!is_edge(l_m, l_n, l_s, l_w, l_e)) {
        out_color = centre;
        return;
    }
    float l_max = max(l_m, max(max(l_n, l_s), max(l_w, l_e)));
    float l_min = min(l_m, min(min(l_n, l_s), min(l_w, l_e)));
    float range = l_max - l_min;

    float l_nw = luma_at(p + ivec2(-1, -1));
    float l_ne = luma_at(p + ivec2(1, -1));
    float l_sw = luma_at(p + ivec2(-1, 1));
    float l_se = luma_at(p + ivec2(1, 1));

    // 2. sub-pixel blend amount
    float average = (2.0 * (l_n + l_s + l_w + l_e) + (l_nw + l_ne + l_sw + l_se)) / 12.0;
    float sub_a = clamp(abs(average - l_m) / range, 0.0, 1.0);
    float sub_b = (3.0 - 2.0 * sub_a) * sub_a * sub_a;
    float sub_offset = sub_b * sub_b * params.subpix;

    // 3. direction. `horizontal`: the edge runs along x, luma changes along y.
    float change_y = abs(l_nw - 2.0 * l_w + l_sw) + 2.0 * abs(l_n - 2.0 * l_m + l_s) + abs(l_ne - 2.0 * l_e + l_se);
    float change_x = abs(l_nw - 2.0 * l_n + l_ne) + 2.0 * abs(l_w - 2.0 * l_m + l_e) + abs(l_sw - 2.0 * l_s + l_se);
    bool horizontal = change_y >= change_x;
    float l_neg = horizontal ? l_n : l_w;
    float l_pos = horizontal ? l_s : l_e;
    float grad_neg = abs(l_neg - l_m);
    float grad_pos = abs(l_pos - l_m);
    float across = horizontal ? inv.y : inv.x;
    float l_edge;
    if (grad_neg >= grad_pos) {
        across = -across;
        l_edge = 0.5 * (l_neg + l_m);
    } else {
        l_edge = 0.5 * (l_pos + l_m);
    }
    float grad_scaled = 0.25 * max(grad_neg, grad_pos);
    vec2 along = horizontal ? vec2(inv.x, 0.0) : vec2(0.0, inv.y);
    vec2 edge_uv = uv;
    if (horizontal) {
        edge_uv.y += 0.5 * across;
    } else {
        edge_uv.x += 0.5 * across;
    }

    // 4. edge search in both directions
    vec2 uv_a = edge_uv - along;
    vec2 uv_b = edge_uv + along;
    float end_a = luma_uv(uv_a) - l_edge;
    float end_b = luma_uv(uv_b) - l_edge;
    bool done_a = abs(end_a) >= grad_scaled;
    bool done_b = abs(end_b) >= grad_scaled;
    for (uint i = 1u; i < SEARCH_STEPS; i++) {
        if (done_a && done_b) {
            break;
        }
        if (!done_a) {
            uv_a -= along * STEPS[i];
            end_a = luma_uv(uv_a) - l_edge;
            done_a = abs(end_a) >= grad_scaled;
        }
        if (!done_b) {
            uv_b += along * STEPS[i];
            end_b = luma_uv(uv_b) - l_edge;
            done_b = abs(end_b) >= grad_scaled;
        }
    }
    float dist_a = horizontal ? uv.x - uv_a.x : uv.y - uv_a.y;
    float dist_b = horizontal ? uv_b.x - uv.x : uv_b.y - uv.y;
    bool nearer_a = dist_a < dist_b;
    float dist = min(dist_a, dist_b);
    float edge_length = dist_a + dist_b;
    bool centre_below = l_m < l_edge;
    bool end_below = nearer_a ? end_a < 0.0 : end_b < 0.0;
    float offset = 0.0;
    if (end_below != centre_below) {
        offset = 0.5 - dist / edge_length;
    }
    offset = max(offset, sub_offset);

    // 5. the final, shifted bilinear fetch
    vec2 final_uv = uv;
    if (horizontal) {
        final_uv.y += offset * across;
    } else {
        final_uv.x += offset * across;
    }
    vec4 color = textureLod(src, final_uv, 0.0);
    out_color = vec4(color.rgb, centre.a);
}
