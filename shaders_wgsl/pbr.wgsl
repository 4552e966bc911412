// glTF 2.0 metallic-roughness BRDF (the specification's Appendix B), the material model of a glTF file's own
// lit materials; the course's scene materials keep scene.wgsl's Blinn-Phong. Inserted into scene.wgsl for
// variants with the `pbr` flag; shaders_glsl/pbr.glsl is its GLSL twin, operation for operation.
//
//   alpha = r^2, r = clamp(roughness, PBR_MIN_ROUGHNESS, 1)         (perceptual roughness -> GGX alpha)
//   D = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2)                 (GGX / Trowbridge-Reitz)
//   V = 0.5 / (n.l sqrt((n.v)^2 (1 - alpha^2) + alpha^2) + n.v sqrt((n.l)^2 (1 - alpha^2) + alpha^2))
//       (Smith joint masking-shadowing, the height-correlated form the Khronos Sample Viewer uses: Appendix B
//        writes the separable product of two G1 terms; both share D, F and the limits tested here)
//   F(f0) = f0 + (1 - f0) (1 - v.h)^5                                (Schlick)
//   dielectric = mix(base / pi, D V, F(0.04)); metal = D V F(base); brdf = mix(dielectric, metal, metallic)
//   radiance = pi * brdf * E * n.l       (pi: the scene's light units, in which a light of intensity 1 shining
//                                         straight onto a white Lambertian surface gives 1, as Blinn-Phong's)
// n.l, n.v, n.h and v.h are clamped to [0, 1]; n.l = 0 gives no light. The roughness clamp: at r = 0 (alpha 0)
// D is 0 / 0 = NaN where n.h = 1 and 0 everywhere else (a black or NaN surface instead of a sharp highlight);
// PBR_MIN_ROUGHNESS = 0.045 (alpha 0.002) keeps D finite in float32 (tests/test_pbr.py checks both).

const PBR_PI: f32 = 3.14159265358979;
const PBR_MIN_ROUGHNESS: f32 = 0.045;
const PBR_DIELECTRIC_F0: f32 = 0.04;

fn pbr_distribution(n_dot_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let k = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (PBR_PI * k * k);
}

fn pbr_visibility(n_dot_l: f32, n_dot_v: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let from_l = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    let from_v = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return 0.5 / (from_l + from_v);
}

fn pbr_schlick(f0: vec3f, v_dot_h: f32) -> vec3f {
    let x = 1.0 - v_dot_h;
    let x2 = x * x;
    return f0 + (vec3f(1.0) - f0) * (x2 * x2 * x);
}

// The half vector of the unit vectors l and v; n when l = -v (their sum is zero).
fn pbr_half(n: vec3f, l: vec3f, v: vec3f) -> vec3f {
    let sum = l + v;
    let len2 = dot(sum, sum);
    return select(n, sum * inverseSqrt(len2), len2 > 1e-20);
}

// GGX's alpha of a perceptual roughness, kept off 0 (PBR_MIN_ROUGHNESS: a mirror's D would be a spike).
fn pbr_alpha(roughness: f32) -> f32 {
    let r = clamp(roughness, PBR_MIN_ROUGHNESS, 1.0);
    return r * r;
}

// Radiance reflected towards v from irradiance E arriving along l (unit vectors; h falls back to n when l = -v).
fn pbr_radiance(n: vec3f, l: vec3f, v: vec3f, base: vec3f, metallic: f32, roughness: f32,
                irradiance: vec3f) -> vec3f {
    let n_dot_l = clamp(dot(n, l), 0.0, 1.0);
    if (n_dot_l <= 0.0) {
        return vec3f(0.0);
    }
    let n_dot_v = clamp(dot(n, v), 0.0, 1.0);
    let h = pbr_half(n, l, v);
    let n_dot_h = clamp(dot(n, h), 0.0, 1.0);
    let v_dot_h = clamp(dot(v, h), 0.0, 1.0);
    let alpha = pbr_alpha(roughness);
    let specular = pbr_distribution(n_dot_h, alpha) * pbr_visibility(n_dot_l, n_dot_v, alpha);
    let dielectric = mix(base / PBR_PI, vec3f(specular), pbr_schlick(vec3f(PBR_DIELECTRIC_F0), v_dot_h));
    let metal = specular * pbr_schlick(base, v_dot_h);
    let brdf = mix(dielectric, metal, vec3f(clamp(metallic, 0.0, 1.0)));
    return PBR_PI * brdf * irradiance * n_dot_l;
}
