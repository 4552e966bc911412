// Image-based lighting for glTF metallic-roughness materials (-DIBL, included after pbr.glsl): the GLSL twin of
// shaders_wgsl/ibl_shading.wgsl, operation for operation (the formulas are in its header). The maps are one
// read-only storage buffer of vec4 rows in core/course/ibl_maps.py's pack() layout, at set 2 binding 11.

layout(std430, set = 2, binding = 11) readonly buffer IblMaps {
    vec4 ibl_maps[];
};

const uint IBL_IRRADIANCE_W = 32u;
const uint IBL_IRRADIANCE_H = 16u;
const uint IBL_PREFILTER_W = 64u;
const uint IBL_PREFILTER_H = 32u;
const uint IBL_LEVELS = 5u;
const uint IBL_LUT = 32u;
const uint IBL_PREFILTER_AT = IBL_IRRADIANCE_W * IBL_IRRADIANCE_H;
const uint IBL_LUT_AT = IBL_PREFILTER_AT + IBL_LEVELS * IBL_PREFILTER_W * IBL_PREFILTER_H;

uint ibl_texel(vec3 d, uint w, uint h) {
    float u = atan(d.x, -d.z) / (2.0 * PBR_PI) + 0.5;
    float v = acos(clamp(d.y, -1.0, 1.0)) / PBR_PI;
    uint x = min(uint(max(u, 0.0) * float(w)), w - 1u);
    uint y = min(uint(max(v, 0.0) * float(h)), h - 1u);
    return y * w + x;
}

vec2 ibl_cell(uint x, uint y) {
    return ibl_maps[IBL_LUT_AT + y * IBL_LUT + x].xy;
}

vec2 ibl_table(float n_dot_v, float roughness) {
    float last = float(IBL_LUT - 1u);
    float x = clamp(n_dot_v * float(IBL_LUT) - 0.5, 0.0, last);
    float y = clamp(roughness * float(IBL_LUT) - 0.5, 0.0, last);
    uint x0 = uint(x);
    uint y0 = uint(y);
    uint x1 = min(x0 + 1u, IBL_LUT - 1u);
    uint y1 = min(y0 + 1u, IBL_LUT - 1u);
    float tx = x - float(x0);
    float ty = y - float(y0);
    vec2 row0 = mix(ibl_cell(x0, y0), ibl_cell(x1, y0), tx);
    vec2 row1 = mix(ibl_cell(x0, y1), ibl_cell(x1, y1), tx);
    return mix(row0, row1, ty);
}

// The prefiltered radiance along r at roughness `rough` (in [0, 1]): levels k0 and k0 + 1 mixed.
vec3 ibl_prefiltered(vec3 r, float rough) {
    float k = rough * float(IBL_LEVELS - 1u);
    uint k0 = min(uint(k), IBL_LEVELS - 2u);
    float t = k - float(k0);
    uint level = IBL_PREFILTER_W * IBL_PREFILTER_H;
    uint at = IBL_PREFILTER_AT + k0 * level + ibl_texel(r, IBL_PREFILTER_W, IBL_PREFILTER_H);
    return mix(ibl_maps[at].rgb, ibl_maps[at + level].rgb, t);
}

vec3 ibl_radiance(vec3 n, vec3 v, vec3 base, float metallic, float roughness) {
    float n_dot_v = clamp(dot(n, v), 1e-4, 1.0);
    vec3 r = 2.0 * n_dot_v * n - v;
    float rough = clamp(roughness, 0.0, 1.0);
    vec3 prefiltered = ibl_prefiltered(r, rough);
    vec2 ab = ibl_table(n_dot_v, rough);
    float m = clamp(metallic, 0.0, 1.0);
    vec3 f0 = mix(vec3(PBR_DIELECTRIC_F0), base, m);
    float x = 1.0 - n_dot_v;
    float fresnel = PBR_DIELECTRIC_F0 + (1.0 - PBR_DIELECTRIC_F0) * (x * x * x * x * x);
    vec3 irradiance = ibl_maps[ibl_texel(n, IBL_IRRADIANCE_W, IBL_IRRADIANCE_H)].rgb;
    vec3 diffuse = (1.0 - m) * base * irradiance * (1.0 - fresnel);
    return diffuse + prefiltered * (f0 * ab.x + ab.y);
}

// A Fresnel-free GGX layer's reflection of the environment (ibl_shading.wgsl's ibl_layer).
vec3 ibl_layer(vec3 n, vec3 v, float roughness) {
    float n_dot_v = clamp(dot(n, v), 1e-4, 1.0);
    vec3 mirror = 2.0 * n_dot_v * n - v;
    float rough = clamp(roughness, 0.0, 1.0);
    vec2 ab = ibl_table(n_dot_v, rough);
    return ibl_prefiltered(mirror, rough) * (ab.x + ab.y);
}
