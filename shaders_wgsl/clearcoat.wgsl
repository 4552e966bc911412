// KHR_materials_clearcoat: a clear coat layered over the glTF metallic-roughness material (the `clearcoat` variant
// flag, inserted after pbr.wgsl and ibl_shading.wgsl); shaders_glsl/clearcoat.glsl is its GLSL twin. The
// extension's layering, with the coat's normal nc (the geometric normal, or the clearcoat normal map's) and
// weight c = clearcoatFactor x the clearcoat texture's R:
//
//   Fc = 0.04 + 0.96 (1 - |nc.v|)^5                      (Schlick at F0 0.04, ior 1.5, on the coat's normal)
//   f  = f_base (1 - c Fc) + c Fc D(nc, rc) V(nc, rc)    (the layer: the Fresnel-free GGX lobe of pbr.wgsl,
//                                                         alpha = rc^2, rc = clearcoatRoughnessFactor x texture G,
//                                                         clamped as the base roughness is)
//
// Light by light that is (1 - c Fc) times the base radiance plus c Fc pi D V E (nc.l). The base's ambient term,
// image-based lighting and emission are the base's too (the spec layers the coat over all of it). What the coat
// itself reflects of the surroundings: with [environment], the prefiltered map at the coat's roughness along nc's
// reflection times the split-sum table's (A + B) (ibl_shading.wgsl's ibl_layer); without one, the uniform ambient
// radiance times 1 (the layer's reflectance of a uniform sky taken as its mirror limit). The occlusion map scales
// both ambient terms.

// The coat of this fragment (set by fs_main before shading, from the factors and the coat's textures)
var<private> clearcoat_weight: f32 = 0.0;
var<private> clearcoat_rough: f32 = 0.0;
var<private> clearcoat_normal_texel: vec3f = vec3f(0.5, 0.5, 1.0);
// 1 - c Fc: what the base layer (its lights, ambient and emission) keeps (set by shade)
var<private> clearcoat_base_weight: f32 = 1.0;

fn clearcoat_fresnel(nc: vec3f, v: vec3f) -> f32 {
    let x = 1.0 - clamp(abs(dot(nc, v)), 0.0, 1.0);
    let x2 = x * x;
    return PBR_DIELECTRIC_F0 + (1.0 - PBR_DIELECTRIC_F0) * (x2 * x2 * x);
}

// The coat's radiance towards v from irradiance E along l: pi D V E (nc.l), without the weight c Fc.
fn clearcoat_radiance(nc: vec3f, l: vec3f, v: vec3f, roughness: f32, irradiance: vec3f) -> vec3f {
    let n_dot_l = clamp(dot(nc, l), 0.0, 1.0);
    if (n_dot_l <= 0.0) {
        return vec3f(0.0);
    }
    let n_dot_v = clamp(dot(nc, v), 0.0, 1.0);
    let h = pbr_half(nc, l, v);
    let n_dot_h = clamp(dot(nc, h), 0.0, 1.0);
    let alpha = pbr_alpha(roughness);
    let specular = pbr_distribution(n_dot_h, alpha) * pbr_visibility(n_dot_l, n_dot_v, alpha);
    return PBR_PI * specular * irradiance * n_dot_l;
}
