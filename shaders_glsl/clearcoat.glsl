// KHR_materials_clearcoat (-DCLEARCOAT, included after pbr.glsl and ibl_shading.glsl): the GLSL twin of
// shaders_wgsl/clearcoat.wgsl, operation for operation (the layering is written out there).

// The coat of this fragment (set by main before shading, from the factors and the coat's textures)
float clearcoat_weight = 0.0;
float clearcoat_rough = 0.0;
vec3 clearcoat_normal_texel = vec3(0.5, 0.5, 1.0);
// 1 - c Fc: what the base layer (its lights, ambient and emission) keeps (set by shade)
float clearcoat_base_weight = 1.0;

float clearcoat_fresnel(vec3 nc, vec3 v) {
    float x = 1.0 - clamp(abs(dot(nc, v)), 0.0, 1.0);
    float x2 = x * x;
    return PBR_DIELECTRIC_F0 + (1.0 - PBR_DIELECTRIC_F0) * (x2 * x2 * x);
}

// The coat's radiance towards v from irradiance E along l: pi D V E (nc.l), without the weight c Fc.
vec3 clearcoat_radiance(vec3 nc, vec3 l, vec3 v, float roughness, vec3 irradiance) {
    float n_dot_l = clamp(dot(nc, l), 0.0, 1.0);
    if (n_dot_l <= 0.0) {
        return vec3(0.0);
    }
    float n_dot_v = clamp(dot(nc, v), 0.0, 1.0);
    vec3 h = pbr_half(nc, l, v);
    float n_dot_h = clamp(dot(nc, h), 0.0, 1.0);
    float alpha = pbr_alpha(roughness);
    float specular = pbr_distribution(n_dot_h, alpha) * pbr_visibility(n_dot_l, n_dot_v, alpha);
    return PBR_PI * specular * irradiance * n_dot_l;
}
