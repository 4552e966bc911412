// glTF 2.0 metallic-roughness BRDF (Appendix B): the GLSL twin of shaders_wgsl/pbr.wgsl, operation for operation
// (the formulas, the roughness clamp and the light units are written out there). Included by scene.frag for
// variants compiled with -DPBR.

const float PBR_PI = 3.14159265358979;
const float PBR_MIN_ROUGHNESS = 0.045;
const float PBR_DIELECTRIC_F0 = 0.04;

float pbr_distribution(float n_dot_h, float alpha) {
    float a2 = alpha * alpha;
    float k = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (PBR_PI * k * k);
}

float pbr_visibility(float n_dot_l, float n_dot_v, float alpha) {
    float a2 = alpha * alpha;
    float from_l = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    float from_v = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return 0.5 / (from_l + from_v);
}

vec3 pbr_schlick(vec3 f0, float v_dot_h) {
    float x = 1.0 - v_dot_h;
    float x2 = x * x;
    return f0 + (vec3(1.0) - f0) * (x2 * x2 * x);
}

// The half vector of the unit vectors l and v; n when l = -v (their sum is zero).
vec3 pbr_half(vec3 n, vec3 l, vec3 v) {
    vec3 sum = l + v;
    float len2 = dot(sum, sum);
    return len2 > 1e-20 ? sum * inversesqrt(len2) : n;
}

// GGX's alpha of a perceptual roughness, kept off 0 (PBR_MIN_ROUGHNESS: a mirror's D would be a spike).
float pbr_alpha(float roughness) {
    float r = clamp(roughness, PBR_MIN_ROUGHNESS, 1.0);
    return r * r;
}

vec3 pbr_radiance(vec3 n, vec3 l, vec3 v, vec3 base, float metallic, float roughness, vec3 irradiance) {
    float n_dot_l = clamp(dot(n, l), 0.0, 1.0);
    if (n_dot_l <= 0.0) {
        return vec3(0.0);
    }
    float n_dot_v = clamp(dot(n, v), 0.0, 1.0);
    vec3 h = pbr_half(n, l, v);
    float n_dot_h = clamp(dot(n, h), 0.0, 1.0);
    float v_dot_h = clamp(dot(v, h), 0.0, 1.0);
    float alpha = pbr_alpha(roughness);
    float specular = pbr_distribution(n_dot_h, alpha) * pbr_visibility(n_dot_l, n_dot_v, alpha);
    vec3 dielectric = mix(base / PBR_PI, vec3(specular), pbr_schlick(vec3(PBR_DIELECTRIC_F0), v_dot_h));
    vec3 metal = specular * pbr_schlick(base, v_dot_h);
    vec3 brdf = mix(dielectric, metal, vec3(clamp(metallic, 0.0, 1.0)));
    return PBR_PI * brdf * irradiance * n_dot_l;
}
