#version 450
// The scene's post chain on the raw path: every per-pixel effect of the chain, composed in ONE
// fragment shader of subpass 1, reading the resolved scene image as an input attachment.
//
// subpassLoad reads only the pixel under the fragment (it takes no coordinates), so only effects
// that are functions of one pixel (plus its position) can run here: tonemap, vignette, grayscale,
// sepia, srgb. FXAA and sharpen read neighbours: each runs in a render pass of its own that samples
// the previous result (post_fxaa.frag, post_sharpen.frag; wgpurender/raw_path/post/neighbourhood.py).
// Each effect's arithmetic is its WGSL twin's (shaders_wgsl/post_<effect>.wgsl), operation for operation.
//
// The chain is data, not code: a uniform block lists the steps (kind + up to three parameters) and
// the loop applies them in order, so one pipeline serves every chain. The loop bound comes from a
// uniform, so every fragment takes the same path (dynamically uniform control flow).
//
// F16_BETWEEN_STEPS (a -D flag, for tests only): round the colour to float16 after every step but
// the last, as the wgpu path's rgba16float ping-pong textures do between its separate passes
// (only meaningful for an rgba16float scene image, the format of those textures then).

#define TONEMAP 0
#define VIGNETTE 1
#define GRAYSCALE 2
#define SEPIA 3
#define SRGB 4

layout(input_attachment_index = 0, set = 0, binding = 0) uniform subpassInput scene;

struct Step {
    int kind;   // @0 of each 16-byte element
    float p0;   // @4
    float p1;   // @8
    float p2;   // @12
};

layout(std140, set = 0, binding = 1) uniform Chain {
    vec2 size;    // @0: the image size in pixels (the vignette's uv)
    int count;    // @8: steps used
    Step steps[MAX_POST_STEPS];  // @16, 16 bytes each
} chain;

layout(location = 0) out vec4 out_color;

const vec3 LUMA_709 = vec3(0.2126, 0.7152, 0.0722);

vec3 aces_fitted(vec3 c) {
    vec3 a = vec3(dot(vec3(0.59719, 0.35458, 0.04823), c),
                  dot(vec3(0.07600, 0.90834, 0.01566), c),
                  dot(vec3(0.02840, 0.13383, 0.83777), c));
    vec3 b = (a * (a + 0.0245786) - 0.000090537) / (a * (0.983729 * a + 0.4329510) + 0.238081);
    vec3 o = vec3(dot(vec3(1.60475, -0.53108, -0.07367), b),
                  dot(vec3(-0.10208, 1.10813, -0.00605), b),
                  dot(vec3(-0.00327, -0.07276, 1.07602), b));
    return clamp(o, vec3(0.0), vec3(1.0));
}

// p0: exposure, p1: operator (0 ACES fitted, 1 Reinhard)
vec3 tonemap(vec3 rgb, Step s) {
    vec3 hdr = min(max(rgb, vec3(0.0)), vec3(65504.0));
    vec3 c = min(hdr * s.p0, vec3(65504.0));
    if (s.p1 < 0.5) {
        return aces_fitted(c);
    }
    return c / (1.0 + c);
}

// p0: strength, p1: radius, p2: softness
vec3 vignette(vec3 rgb, Step s) {
    vec2 uv = gl_FragCoord.xy / chain.size;
    float d = length(uv - vec2(0.5)) * sqrt(2.0);
    float factor = 1.0 - s.p0 * smoothstep(s.p1, s.p1 + s.p2, d);
    return rgb * factor;
}

// p0: amount
vec3 grayscale(vec3 rgb, Step s) {
    float y = dot(rgb, LUMA_709);
    return mix(rgb, vec3(y), s.p0);
}

// p0: amount
vec3 sepia(vec3 c, Step s) {
    vec3 toned = vec3(dot(vec3(0.393, 0.769, 0.189), c),
                      dot(vec3(0.349, 0.686, 0.168), c),
                      dot(vec3(0.272, 0.534, 0.131), c));
    return mix(c, toned, s.p0);
}

// p0: 1 = apply the sRGB curve (plain 8-bit output), 0 = pass through (-srgb or float output)
vec3 srgb(vec3 linear, Step s) {
    if (s.p0 < 0.5) {
        return linear;
    }
    vec3 x = clamp(linear, vec3(0.0), vec3(1.0));
    vec3 lo = 12.92 * x;
    vec3 hi = 1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055;
    return mix(hi, lo, lessThanEqual(x, vec3(0.0031308)));
}

// c as an rgba16float attachment stores it on lavapipe: rounded toward zero (measured: this, not
// packHalf2x16's round-to-nearest, reproduces the wgpu path's intermediates bit for bit). Normal
// float16 range: keep the top 10 mantissa bits; subnormal range (below 2^-14): multiples of 2^-24.
// Values past 65504 do not occur here (tonemap clamps to [0, 1]).
vec4 round_to_f16(vec4 c) {
    vec4 normal = uintBitsToFloat(floatBitsToUint(c) & uvec4(0xFFFFE000u));
    vec4 subnormal = trunc(c * 16777216.0) / 16777216.0;
    return mix(normal, subnormal, lessThan(abs(c), vec4(6.103515625e-05)));
}

void main() {
    vec4 c = subpassLoad(scene);
    for (int i = 0; i < chain.count; i++) {
        Step s = chain.steps[i];
        if (s.kind == TONEMAP) {
            c.rgb = tonemap(c.rgb, s);
        } else if (s.kind == VIGNETTE) {
            c.rgb = vignette(c.rgb, s);
        } else if (s.kind == GRAYSCALE) {
            c.rgb = grayscale(c.rgb, s);
        } else if (s.kind == SEPIA) {
            c.rgb = sepia(c.rgb, s);
        } else if (s.kind == SRGB) {
            c.rgb = srgb(c.rgb, s);
        }
#ifdef F16_BETWEEN_STEPS
        if (i + 1 < chain.count) {
            c = round_to_f16(c);
        }
#endif
    }
    out_color = c;
}
