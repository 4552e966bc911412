#version 450
// Image-based lighting maps from an equirectangular environment, in compute (raw_path/scene/ibl.py): the GLSL twin
// of shaders_wgsl/ibl.wgsl, operation for operation (the formulas are in its header). One pass per variant:
// -DIRRADIANCE, -DPREFILTER (one z slice per level) or -DBRDF_LUT. Buffers: the parameters (std140, the same 32
// bytes as ibl.wgsl's Params), the environment and the result, both vec4 rows.

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, set = 0, binding = 0) uniform Params {
    uvec2 env_size;
    uvec2 out_size;
    uint samples;
    uint levels;
    uint pad0;
    uint pad1;
} params;

layout(std430, set = 0, binding = 1) readonly buffer Environment {
    vec4 env[];
};

layout(std430, set = 0, binding = 2) writeonly buffer Result {
    vec4 result[];
};

const float PI = 3.14159265358979;

vec3 direction(vec2 uv) {
    float phi = (uv.x - 0.5) * 2.0 * PI;
    float theta = uv.y * PI;
    return vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

vec3 env_radiance(vec3 d) {
    float u = atan(d.x, -d.z) / (2.0 * PI) + 0.5;
    float v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    uint x = min(uint(max(u, 0.0) * float(params.env_size.x)), params.env_size.x - 1u);
    uint y = min(uint(max(v, 0.0) * float(params.env_size.y)), params.env_size.y - 1u);
    return env[y * params.env_size.x + x].rgb;
}

vec2 hammersley(uint i, uint n) {
    return vec2((float(i) + 0.5) / float(n), float(bitfieldReverse(i)) * 2.3283064365386963e-10);
}

// A GGX-distributed half vector around n (pdf D(h) n.h).
vec3 ggx_half(vec2 xi, float alpha, vec3 n) {
    float a2 = alpha * alpha;
    float phi = 2.0 * PI * xi.x;
    float cos_t = sqrt((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y));
    float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    vec3 up = abs(n.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    vec3 t = normalize(cross(up, n));
    vec3 b = cross(n, t);
    return normalize(t * (sin_t * cos(phi)) + b * (sin_t * sin(phi)) + n * cos_t);
}

#ifdef IRRADIANCE
void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= params.out_size.x || id.y >= params.out_size.y) {
        return;
    }
    vec3 n = direction((vec2(id.xy) + 0.5) / vec2(params.out_size));
    uint w = params.env_size.x;
    uint h = params.env_size.y;
    vec3 sum = vec3(0.0);
    for (uint y = 0u; y < h; y++) {
        float band = 2.0 * PI / float(w) * (cos(float(y) / float(h) * PI) - cos(float(y + 1u) / float(h) * PI));
        for (uint x = 0u; x < w; x++) {
            vec3 l = direction((vec2(float(x), float(y)) + 0.5) / vec2(float(w), float(h)));
            sum += env[y * w + x].rgb * max(dot(n, l), 0.0) * band;
        }
    }
    result[id.y * params.out_size.x + id.x] = vec4(sum / PI, 1.0);
}
#endif

#ifdef PREFILTER
// ibl.wgsl's texel_under, inside and mirror_texel: level 0 by integer arithmetic (see its header).
uint texel_under(uint i, uint size, uint count) {
    return ((2u * i + 1u) * count) / (2u * size);
}

bool inside(uint k, uint i, uint size, uint count) {
    return ((2u * k + 1u) * size) / (2u * count) == i;
}

vec3 mirror_texel(uvec2 texel) {
    uint w = params.env_size.x;
    uint h = params.env_size.y;
    uvec2 size = params.out_size;
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (uint y = (texel.y * h) / size.y; y < min(((texel.y + 1u) * h) / size.y + 1u, h); y++) {
        if (!inside(y, texel.y, size.y, h)) {
            continue;
        }
        float band = 2.0 * PI / float(w) * (cos(float(y) / float(h) * PI) - cos(float(y + 1u) / float(h) * PI));
        for (uint x = (texel.x * w) / size.x; x < min(((texel.x + 1u) * w) / size.x + 1u, w); x++) {
            if (inside(x, texel.x, size.x, w)) {
                sum += env[y * w + x].rgb * band;
                weight += band;
            }
        }
    }
    if (weight > 0.0) {
        return sum / weight;
    }
    return env[texel_under(texel.y, size.y, h) * w + texel_under(texel.x, size.x, w)].rgb;
}

void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= params.out_size.x || id.y >= params.out_size.y || id.z >= params.levels) {
        return;
    }
    uint index = (id.z * params.out_size.y + id.y) * params.out_size.x + id.x;
    if (id.z == 0u) {
        result[index] = vec4(mirror_texel(id.xy), 1.0);
        return;
    }
    vec3 n = direction((vec2(id.xy) + 0.5) / vec2(params.out_size));
    float roughness = float(id.z) / float(max(params.levels - 1u, 1u));
    float alpha = roughness * roughness;
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (uint i = 0u; i < params.samples; i++) {
        vec3 hv = ggx_half(hammersley(i, params.samples), alpha, n);
        vec3 l = 2.0 * dot(n, hv) * hv - n;
        float n_dot_l = dot(n, l);
        if (n_dot_l > 0.0) {
            sum += env_radiance(l) * n_dot_l;
            weight += n_dot_l;
        }
    }
    result[index] = vec4(sum / max(weight, 1e-6), 1.0);
}
#endif

#ifdef BRDF_LUT
float visibility(float n_dot_l, float n_dot_v, float alpha) {
    float a2 = alpha * alpha;
    return 0.5 / (n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2) + n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2));
}

void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= params.out_size.x || id.y >= params.out_size.y) {
        return;
    }
    float n_dot_v = (float(id.x) + 0.5) / float(params.out_size.x);
    float roughness = (float(id.y) + 0.5) / float(params.out_size.y);
    float alpha = roughness * roughness;
    vec3 v = vec3(sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v);
    vec3 n = vec3(0.0, 0.0, 1.0);
    vec2 ab = vec2(0.0);
    for (uint i = 0u; i < params.samples; i++) {
        vec3 hv = ggx_half(hammersley(i, params.samples), alpha, n);
        vec3 l = 2.0 * dot(v, hv) * hv - v;
        float n_dot_l = l.z;
        float n_dot_h = max(hv.z, 1e-6);
        float v_dot_h = max(dot(v, hv), 0.0);
        if (n_dot_l > 0.0) {
            float g_vis = visibility(n_dot_l, n_dot_v, alpha) * 4.0 * n_dot_l * v_dot_h / n_dot_h;
            float fc = pow(1.0 - v_dot_h, 5.0);
            ab += vec2((1.0 - fc) * g_vis, fc * g_vis);
        }
    }
    result[id.y * params.out_size.x + id.x] = vec4(ab / float(params.samples), 0.0, 1.0);
}
#endif
