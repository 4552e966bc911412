#version 450
#extension GL_GOOGLE_include_directive : require
// The scene's fragment shader on the raw path: the GLSL twin of shaders_wgsl/scene.wgsl's fs_main,
// normalized Blinn-Phong in linear light with normal and roughness maps (the model is explained in
// scene.wgsl's header; the arithmetic here follows it operation for operation), or with -DPBR the glTF
// metallic-roughness BRDF of pbr.glsl (pbr.wgsl's twin). Variants: -D flags, see scene.vert.
//
// Material data is the course's way: per-draw factors in push constants, textures as
// COMBINED_IMAGE_SAMPLER descriptors in set 2 (the wgpu path, which cannot express combined
// samplers, binds one sampler and separate textures; lavapipe samples both alike).

#ifdef LIGHTING
struct DirectionalLight {
    vec4 direction;  // the way the light travels
    vec4 radiance;
};
struct PointLight {
    vec4 position;  // w: range (0: none)
    vec4 radiance;  // w: spot cone offset
    vec4 spot;      // the spot's axis, w: cone scale (a plain point light: scale 0, offset 1)
};
#endif

layout(std140, set = 0, binding = 0) uniform Camera {
    mat4 proj;          // @0
    mat4 view;          // @64
    vec4 eye;           // @128
#ifdef LIGHTING
    vec4 ambient;       // @144
    uvec4 light_counts; // @160 (the loops use the compile-time counts)
    DirectionalLight directional[MAX_LIGHTS];  // @176, 32 bytes each
    PointLight point[MAX_LIGHTS];              // @176 + 32 * MAX_LIGHTS, 48 bytes each
#endif
} camera;

layout(push_constant) uniform Material {
    vec4 base_color;        // @0
#ifdef LIGHTING
    float roughness;        // @16
    float normal_strength;  // @20
#ifdef PBR
    float metallic;         // @24 (the glTF metallic factor takes specular's place)
#else
    float specular;         // @24
#endif
#endif
#ifdef ALPHA_MASK
    float alpha_cutoff;     // @28 lit, @16 unlit
#endif
#ifdef OCCLUSION_MAP
    float occlusion_strength;  // next float
#endif
#ifdef CLEARCOAT
    float clearcoat;               // next float: KHR_materials_clearcoat's factor,
    float clearcoat_roughness;     // its roughness factor
    float clearcoat_normal_scale;  // and its normal texture's scale
#endif
#ifdef EMISSIVE
    vec4 emissive;          // rgb; on the next multiple of 16 bytes (std430)
#endif
} material;

#ifdef ALBEDO_MAP
layout(set = 2, binding = 2) uniform sampler2D albedo_tex;
#endif
#ifdef NORMAL_MAP
layout(set = 2, binding = 3) uniform sampler2D normal_tex;
#endif
#ifdef ROUGHNESS_MAP
layout(set = 2, binding = 4) uniform sampler2D roughness_tex;
#endif
#ifdef EMISSIVE_MAP
layout(set = 2, binding = 7) uniform sampler2D emissive_tex;
#endif
#ifdef OCCLUSION_MAP
layout(set = 2, binding = 9) uniform sampler2D occlusion_tex;
float ambient_occlusion = 1.0;  // the ambient term's factor for this fragment (set by main before shading)
#endif
#ifdef PBR
float pbr_metallic = 0.0;  // the metallic factor of this fragment (set by main before shading)
#include "pbr.glsl"
#endif
#ifdef IBL
#include "ibl_shading.glsl"
#endif
#ifdef CLEARCOAT_MAP
layout(set = 2, binding = 12) uniform sampler2D clearcoat_tex;
#endif
#ifdef CLEARCOAT_ROUGHNESS_MAP
layout(set = 2, binding = 14) uniform sampler2D clearcoat_roughness_tex;
#endif
#ifdef CLEARCOAT_NORMAL_MAP
layout(set = 2, binding = 16) uniform sampler2D clearcoat_normal_tex;
#endif
#ifdef CLEARCOAT
#include "clearcoat.glsl"
#endif

#ifdef LIGHTING
layout(location = 0) in vec3 v_world_position;
layout(location = 1) in vec3 v_normal;
#endif
#ifdef UV
layout(location = 2) in vec2 v_uv;
#endif
#ifdef TANGENT
layout(location = 3) in vec4 v_tangent;
#endif
#ifdef VERTEX_COLOR
layout(location = 4) in vec4 v_color;
#endif
#ifdef UV1
layout(location = 5) in vec2 v_uv1;
#endif
#ifdef UV2
layout(location = 6) in vec2 v_uv2;
#endif
#ifdef UV3
layout(location = 7) in vec2 v_uv3;
#endif
#ifdef UV4
layout(location = 8) in vec2 v_uv4;
#endif
// Each map samples <MAP>_UV: v_uv, or v_uv<k> when glslc gets -D<MAP>_UV=v_uv<k> (a further coordinate slot)
#ifndef ALBEDO_UV
#define ALBEDO_UV v_uv
#endif
#ifndef NORMAL_UV
#define NORMAL_UV v_uv
#endif
#ifndef ROUGHNESS_UV
#define ROUGHNESS_UV v_uv
#endif
#ifndef EMISSIVE_UV
#define EMISSIVE_UV v_uv
#endif
#ifndef OCCLUSION_UV
#define OCCLUSION_UV v_uv
#endif
#ifndef CLEARCOAT_UV
#define CLEARCOAT_UV v_uv
#endif
#ifndef CLEARCOAT_ROUGHNESS_UV
#define CLEARCOAT_ROUGHNESS_UV v_uv
#endif
#ifndef CLEARCOAT_NORMAL_UV
#define CLEARCOAT_NORMAL_UV v_uv
#endif

layout(location = 0) out vec4 out_color;

#ifdef LIGHTING
// v / |v|, or `fallback` when v is (nearly) zero or not finite.
vec3 safe_normalize(vec3 v, vec3 fallback) {
    float len2 = dot(v, v);
    if (len2 > 1e-20 && len2 < 1e30) {
        return v * inversesqrt(len2);
    }
    return fallback;
}

vec3 geometric_normal() {
#ifdef DOUBLE_SIDED
    // a back face is lit as the surface's other side (glTF doubleSided)
    return safe_normalize(gl_FrontFacing ? v_normal : -v_normal, vec3(0.0, 0.0, 1.0));
#else
    return safe_normalize(v_normal, vec3(0.0, 0.0, 1.0));
#endif
}

#ifdef TANGENT
// n perturbed by a tangent-space normal map's texel, its xy scaled by `strength`.
vec3 mapped_normal(vec3 n, vec3 texel, float strength) {
    vec3 t_raw = v_tangent.xyz - n * dot(n, v_tangent.xyz);
    if (dot(t_raw, t_raw) <= 1e-20) {
        return n;
    }
    vec3 t = normalize(t_raw);
    vec3 b = (v_tangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
    vec3 m = texel * 2.0 - 1.0;
    m = vec3(m.xy * strength, m.z);
    return safe_normalize(t * m.x + b * m.y + n * m.z, n);
}
#endif

vec3 surface_normal(vec3 normal_texel) {
    vec3 n = geometric_normal();
#ifdef NORMAL_MAP
    return mapped_normal(n, normal_texel, material.normal_strength);
#else
    return n;
#endif
}

#ifdef CLEARCOAT
// The coat's own normal: the geometric one, perturbed only by the clearcoat normal map (not the base's).
vec3 clearcoat_normal() {
    vec3 n = geometric_normal();
#ifdef CLEARCOAT_NORMAL_MAP
    return mapped_normal(n, clearcoat_normal_texel, material.clearcoat_normal_scale);
#else
    return n;
#endif
}
#endif

#ifndef PBR
float shininess(float roughness) {
    float r = clamp(roughness, 0.0, 1.0);
    float r4 = r * r * r * r;
    return clamp(2.0 / max(r4, 1e-6) - 2.0, 1.0, 4096.0);
}

vec3 blinn_phong(vec3 n, vec3 l, vec3 v, vec3 albedo, float s, vec3 irradiance) {
    float n_dot_l = max(dot(n, l), 0.0);
    vec3 h = safe_normalize(l + v, n);
    float spec = material.specular * (s + 8.0) / 8.0 * pow(max(dot(n, h), 0.0), s);
    return irradiance * n_dot_l * (albedo + vec3(spec));
}
#endif

// A point light's range window and spot cone (scene.wgsl's light_window).
float light_window(PointLight light, float d2, vec3 l) {
    float window = 1.0;
    if (light.position.w > 0.0) {
        float x = d2 / (light.position.w * light.position.w);
        window = clamp(1.0 - x * x, 0.0, 1.0);
    }
    float cone = clamp(dot(light.spot.xyz, -l) * light.spot.w + light.radiance.w, 0.0, 1.0);
    return window * cone * cone;
}

vec3 shade(vec3 albedo, vec3 normal_texel, float roughness) {
    vec3 n = surface_normal(normal_texel);
    // eye.w = 0 for an orthographic camera (eye.xyz the direction towards it): every view vector is parallel
    vec3 v = safe_normalize(camera.eye.xyz - v_world_position * camera.eye.w, n);
#ifndef PBR
    float s = shininess(roughness);
#endif
#ifdef IBL
    vec3 color = ibl_radiance(n, v, albedo, pbr_metallic, roughness);  // the environment replaces the ambient term
#else
    vec3 color = camera.ambient.rgb * albedo;
#endif
#ifdef OCCLUSION_MAP
    color = color * ambient_occlusion;
#endif
#ifdef CLEARCOAT
    vec3 nc = clearcoat_normal();
    float coat_weight = clamp(clearcoat_weight, 0.0, 1.0) * clearcoat_fresnel(nc, v);
#ifdef IBL
    vec3 coat = ibl_layer(nc, v, clearcoat_rough);
#else
    vec3 coat = camera.ambient.rgb;
#endif
#ifdef OCCLUSION_MAP
    coat = coat * ambient_occlusion;
#endif
#endif
#if DIRECTIONAL_LIGHTS > 0
    for (uint i = 0u; i < uint(DIRECTIONAL_LIGHTS); i++) {
        vec3 l = safe_normalize(-camera.directional[i].direction.xyz, n);
#ifdef PBR
        color += pbr_radiance(n, l, v, albedo, pbr_metallic, roughness, camera.directional[i].radiance.rgb);
#ifdef CLEARCOAT
        coat += clearcoat_radiance(nc, l, v, clearcoat_rough, camera.directional[i].radiance.rgb);
#endif
#else
        color += blinn_phong(n, l, v, albedo, s, camera.directional[i].radiance.rgb);
#endif
    }
#endif
#if POINT_LIGHTS > 0
    for (uint i = 0u; i < uint(POINT_LIGHTS); i++) {
        vec3 to_light = camera.point[i].position.xyz - v_world_position;
        float d2 = max(dot(to_light, to_light), 1e-4);
        vec3 l = safe_normalize(to_light, n);
        vec3 irradiance = camera.point[i].radiance.rgb / d2 * light_window(camera.point[i], d2, l);
#ifdef PBR
        color += pbr_radiance(n, l, v, albedo, pbr_metallic, roughness, irradiance);
#ifdef CLEARCOAT
        coat += clearcoat_radiance(nc, l, v, clearcoat_rough, irradiance);
#endif
#else
        color += blinn_phong(n, l, v, albedo, s, irradiance);
#endif
    }
#endif
#ifdef CLEARCOAT
    clearcoat_base_weight = 1.0 - coat_weight;
    color = color * clearcoat_base_weight + coat * coat_weight;
#endif
    return color;
}
#endif

#ifdef SRGB_OUTPUT
// The output is a plain 8-bit format that does not encode: apply the sRGB curve here.
vec3 srgb_encode(vec3 c) {
    vec3 x = clamp(c, vec3(0.0), vec3(1.0));
    return mix(1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055, 12.92 * x, lessThanEqual(x, vec3(0.0031308)));
}
#endif

void main() {
    vec4 base = material.base_color;
#ifdef ALBEDO_MAP
    base = base * texture(albedo_tex, ALBEDO_UV);
#endif
#ifdef VERTEX_COLOR
    base = base * v_color;
#endif
#ifdef EMISSIVE
#ifdef EMISSIVE_MAP
    vec3 emitted = material.emissive.rgb * texture(emissive_tex, EMISSIVE_UV).rgb;
#else
    vec3 emitted = material.emissive.rgb;
#endif
#endif
#ifdef LIGHTING
#ifdef NORMAL_MAP
    vec3 normal_texel = texture(normal_tex, NORMAL_UV).xyz;
#else
    vec3 normal_texel = vec3(0.5, 0.5, 1.0);
#endif
#ifdef ROUGHNESS_MAP
    vec4 roughness_texel = texture(roughness_tex, ROUGHNESS_UV);
    float roughness = material.roughness * roughness_texel.g;
#ifdef PBR
    pbr_metallic = material.metallic * roughness_texel.b;
#endif
#else
    float roughness = material.roughness;
#ifdef PBR
    pbr_metallic = material.metallic;
#endif
#endif
#ifdef OCCLUSION_MAP
    float occlusion_texel = texture(occlusion_tex, OCCLUSION_UV).r;
    ambient_occlusion = 1.0 + material.occlusion_strength * (occlusion_texel - 1.0);
#endif
#ifdef CLEARCOAT
    clearcoat_weight = material.clearcoat;
    clearcoat_rough = material.clearcoat_roughness;
#ifdef CLEARCOAT_MAP
    clearcoat_weight = clearcoat_weight * texture(clearcoat_tex, CLEARCOAT_UV).r;
#endif
#ifdef CLEARCOAT_ROUGHNESS_MAP
    clearcoat_rough = clearcoat_rough * texture(clearcoat_roughness_tex, CLEARCOAT_ROUGHNESS_UV).g;
#endif
#ifdef CLEARCOAT_NORMAL_MAP
    clearcoat_normal_texel = texture(clearcoat_normal_tex, CLEARCOAT_NORMAL_UV).xyz;
#endif
#endif
    vec3 color = shade(base.rgb, normal_texel, roughness);
#else
    vec3 color = base.rgb;
#endif
#ifdef EMISSIVE
#ifdef CLEARCOAT
    color = color + emitted * clearcoat_base_weight;  // the coat lies over the emission too
#else
    color = color + emitted;
#endif
#endif
#ifdef ALPHA_MASK
    if (base.a < material.alpha_cutoff) {
        discard;
    }
    base.a = 1.0;  // glTF MASK: what is kept is opaque
#endif
#ifdef OPAQUE_ALPHA
    base.a = 1.0;  // glTF OPAQUE: the alpha channel is ignored
#endif
#ifdef SRGB_OUTPUT
    out_color = vec4(srgb_encode(color), base.a);
#else
    out_color = vec4(color, base.a);
#endif
}
