// Image-based lighting for glTF metallic-roughness materials (the `ibl` variant flag, inserted after pbr.wgsl):
// the split-sum approximation read from one storage buffer of vec4f rows laid out as core/course/ibl_maps.py's
// pack() writes them (irradiance 32x16, 5 prefiltered levels 64x32, BRDF table 32x32). shaders_glsl/ibl_shading.glsl
// is its GLSL twin, operation for operation.
//
//   r = 2 (n.v) n - v (n.v clamped to [1e-4, 1]); roughness clamped to [0, 1]
//   prefiltered = mix(level k0, level k0 + 1, t) at r's texel, k = roughness (LEVELS - 1), k0 = min(floor k, LEVELS - 2)
//   (A, B) = the table bilinearly at (n.v, roughness), cells at their centres, clamped at the edges
//   F0 = mix(0.04, base, metallic); Fd = 0.04 + 0.96 (1 - n.v)^5
//   radiance = (1 - metallic) base irradiance(n) (1 - Fd) + prefiltered (F0 A + B)
//   a clear coat's layer (ibl_layer): prefiltered (A + B) at the coat's normal and roughness
// Every lookup takes the nearest texel of an equirectangular map (core/course/environment.py's layout).

const IBL_IRRADIANCE_W: u32 = 32u;
const IBL_IRRADIANCE_H: u32 = 16u;
const IBL_PREFILTER_W: u32 = 64u;
const IBL_PREFILTER_H: u32 = 32u;
const IBL_LEVELS: u32 = 5u;
const IBL_LUT: u32 = 32u;
const IBL_PREFILTER_AT: u32 = IBL_IRRADIANCE_W * IBL_IRRADIANCE_H;
const IBL_LUT_AT: u32 = IBL_PREFILTER_AT + IBL_LEVELS * IBL_PREFILTER_W * IBL_PREFILTER_H;

fn ibl_texel(d: vec3f, w: u32, h: u32) -> u32 {
    let u = atan2(d.x, -d.z) / (2.0 * PBR_PI) + 0.5;
    let v = acos(clamp(d.y, -1.0, 1.0)) / PBR_PI;
    let x = min(u32(max(u, 0.0) * f32(w)), w - 1u);
    let y = min(u32(max(v, 0.0) * f32(h)), h - 1u);
    return y * w + x;
}

fn ibl_cell(x: u32, y: u32) -> vec2f {
    return ibl_maps[IBL_LUT_AT + y * IBL_LUT + x].xy;
}

fn ibl_table(n_dot_v: f32, roughness: f32) -> vec2f {
    let last = f32(IBL_LUT - 1u);
    let x = clamp(n_dot_v * f32(IBL_LUT) - 0.5, 0.0, last);
    let y = clamp(roughness * f32(IBL_LUT) - 0.5, 0.0, last);
    let x0 = u32(x);
    let y0 = u32(y);
    let x1 = min(x0 + 1u, IBL_LUT - 1u);
    let y1 = min(y0 + 1u, IBL_LUT - 1u);
    let tx = x - f32(x0);
    let ty = y - f32(y0);
    let row0 = mix(ibl_cell(x0, y0), ibl_cell(x1, y0), tx);
    let row1 = mix(ibl_cell(x0, y1), ibl_cell(x1, y1), tx);
    return mix(row0, row1, ty);
}

// The prefiltered radiance along r at roughness `rough` (in [0, 1]): levels k0 and k0 + 1 mixed.
fn ibl_prefiltered(r: vec3f, rough: f32) -> vec3f {
    let k = rough * f32(IBL_LEVELS - 1u);
    let k0 = min(u32(k), IBL_LEVELS - 2u);
    let t = k - f32(k0);
    let level = IBL_PREFILTER_W * IBL_PREFILTER_H;
    let at = IBL_PREFILTER_AT + k0 * level + ibl_texel(r, IBL_PREFILTER_W, IBL_PREFILTER_H);
    return mix(ibl_maps[at].rgb, ibl_maps[at + level].rgb, t);
}

fn ibl_radiance(n: vec3f, v: vec3f, base: vec3f, metallic: f32, roughness: f32) -> vec3f {
    let n_dot_v = clamp(dot(n, v), 1e-4, 1.0);
    let r = 2.0 * n_dot_v * n - v;
    let rough = clamp(roughness, 0.0, 1.0);
    let prefiltered = ibl_prefiltered(r, rough);
    let ab = ibl_table(n_dot_v, rough);
    let m = clamp(metallic, 0.0, 1.0);
    let f0 = mix(vec3f(PBR_DIELECTRIC_F0), base, m);
    let x = 1.0 - n_dot_v;
    let fresnel = PBR_DIELECTRIC_F0 + (1.0 - PBR_DIELECTRIC_F0) * (x * x * x * x * x);
    let irradiance = ibl_maps[ibl_texel(n, IBL_IRRADIANCE_W, IBL_IRRADIANCE_H)].rgb;
    let diffuse = (1.0 - m) * base * irradiance * (1.0 - fresnel);
    return diffuse + prefiltered * (f0 * ab.x + ab.y);
}

// A Fresnel-free GGX layer's reflection of the environment (KHR_materials_clearcoat's coat, clearcoat.wgsl):
// the split sum with F = 1, prefiltered x (A + B), at the layer's normal and roughness.
fn ibl_layer(n: vec3f, v: vec3f, roughness: f32) -> vec3f {
    let n_dot_v = clamp(dot(n, v), 1e-4, 1.0);
    let mirror = 2.0 * n_dot_v * n - v;
    let rough = clamp(roughness, 0.0, 1.0);
    let ab = ibl_table(n_dot_v, rough);
    return ibl_prefiltered(mirror, rough) * (ab.x + ab.y);
}
