// The scene shader: one template, specialised per material variant (wgpurender/wgpu_path/scene/shader_interface.py).
//
// Preprocessing (wgpurender/core/shaders/shader_variants.specialise): "#if FEATURE" keeps code for the plan's
// variant flags (albedo_map, lighting, normal_map, roughness_map, flip_v, srgb_output; from a model file's
// own materials: vertex_color, alpha_mask, double_sided) and the derived
// ones (uv: any texture; directional_lights / point_lights: that count > 0; immediates: push constants
// available; instance_attributes: the plan's instance_data is "vertex", so the Object blocks arrive as
// per-instance vertex attributes and the material group is 1, not 2). The STRUCTS placeholder gets the declarations generated from the Python Struct
// definitions; the light counts are compile-time constants, so each loop has a fixed trip count.
// An unlit variant keeps none of the lighting code, no normal/tangent attribute and no light struct.
//
// Shading model: normalized Blinn-Phong, in linear light. The course teaches Blinn-Phong, and the
// normalized form keeps highlights energy-plausible as the exponent changes while every term stays a
// closed form the tests can evaluate in numpy:
//     L = ambient * albedo
//       + sum over lights  E * max(n.l, 0) * (albedo + specular * (s + 8) / 8 * max(n.h, 0)^s)
// which is pi * BRDF * E * n.l with BRDF = albedo / pi + specular * (s + 8) / (8 pi) * (n.h)^s, so a
// light of intensity 1 shining straight onto a white surface gives exactly 1. The exponent comes
// from roughness r (material roughness times the roughness map's G channel):
//     s = clamp(2 / r^4 - 2, 1, 4096)     (the Beckmann-matched Blinn-Phong exponent)
// `specular` is the dielectric reflectance 0.04 (no Fresnel term).
// Lights: E = colour * intensity. Directional lights travel along `direction` (l = -direction).
// Point lights fall off with the inverse square, E = colour * intensity / max(d^2, 1e-4), so intensity is
// the irradiance at 1 unit; a model file's KHR_lights_punctual lights may add a range window and a spot cone
// (light_window; core/scene/gltf_lights.py converts their units).
// Normal mapping (tangent space, +Y up, linear texels): m = texel * 2 - 1, m.xy *= normal_strength,
// T = Gram-Schmidt of the tangent against N, B = w * cross(N, T) (w = tangent.w times the sign of
// det(world)), n' = normalize(T m.x + B m.y + N m.z). Every normalisation is guarded: a zero-length
// vector falls back to a stated default instead of producing NaN.
// Model-file materials (core/scene/gltf_materials.py): base = base_color * albedo texel * vertex colour;
// alpha_mask discards fragments whose alpha is below material.alpha_cutoff (after every texture sample) and
// writes the rest with alpha 1, as opaque_alpha writes every fragment (glTF OPAQUE ignores alpha);
// double_sided turns the normal around on back faces before lighting (glTF's rule).
// Each texture has its own sampler (glTF: filters and per-axis wrap per texture). emissive adds
// material.emissive.rgb (times the sRGB emissive texel with emissive_map) to the shaded colour;
// occlusion_map scales the ambient term by 1 + strength * (texel.r - 1) (lit variants only).
// pbr (a glTF file's lit metallic-roughness material): each light's term is pbr.wgsl's pbr_radiance, not the
// Blinn-Phong term, with metallic = material.metallic (times the metallic-roughness texture's B channel with
// roughness_map, whose G channel is the roughness as above); the ambient term stays ambient * base colour.
// ibl (a pbr material in a scene with an [environment]): ibl_shading.wgsl's image-based lighting takes the ambient
// term's place (times the occlusion factor with occlusion_map); the lights add to it as above.
// clearcoat (a pbr material with KHR_materials_clearcoat; clearcoat_map, clearcoat_roughness_map and
// clearcoat_normal_map its textures): clearcoat.wgsl's coat layered over everything the base shades, emission too.
// tangent (derived: normal_map or clearcoat_normal_map) carries the tangent attribute.
// uv1 .. uv4 (derived from the "<map>_uv<k>" flags): the mesh's further texture coordinate slots (a glTF material
// whose textures sample several TEXCOORD sets or transforms, each applied at load: core/models/gltf_geometry
// .uv_slots); each map samples in.{{<MAP>_UV}}, which shader_interface fills with "uv" or "uv<k>". Only model
// files' materials have them, and those never flip v (flip_v is a scene material's key).

{{STRUCTS}}

const DIRECTIONAL_LIGHTS: u32 = {{DIRECTIONAL_LIGHTS}}u;
const POINT_LIGHTS: u32 = {{POINT_LIGHTS}}u;

@group(0) @binding(0) var<uniform> camera: Camera;
#if instance_attributes
// Every instance's Object block (core/plan/batches.py packs them) in a vertex buffer stepped once per instance,
// from the draw's first_instance on: no storage buffer in the vertex stage (core/plan/instance_data.py).
struct InstanceIn {
    @location(9) world0: vec4f,
    @location(10) world1: vec4f,
    @location(11) world2: vec4f,
    @location(12) world3: vec4f,
#if lighting
    @location(13) normal0: vec3f,
    @location(14) normal1: vec3f,
    @location(15) normal2_mirror: vec4f,  // the third column, and the mirror sign in its padding (vertex_blocks)
#endif
};
#else
// Every instance's Object (world, normal matrix, mirror) in one storage buffer: a draw's instances start at
// its first_instance, which instance_index includes (core/plan/batches.py packs the array).
@group(1) @binding(0) var<storage, read> objects: array<Object>;
#if culled
// A GPU-culled draw (scene_cull.wgsl): its visible instances' indices, from its first_instance on.
@group(1) @binding(1) var<storage, read> visible: array<u32>;
#endif
#endif
#if immediates
var<immediate> material: Material;
#else
@group({{MATERIAL_GROUP}}) @binding(0) var<uniform> material: Material;
#endif
#if albedo_map
@group({{MATERIAL_GROUP}}) @binding(1) var albedo_sampler: sampler;
@group({{MATERIAL_GROUP}}) @binding(2) var albedo_tex: texture_2d<f32>;
#endif
#if normal_map
@group({{MATERIAL_GROUP}}) @binding(3) var normal_tex: texture_2d<f32>;
@group({{MATERIAL_GROUP}}) @binding(5) var normal_sampler: sampler;
#endif
#if roughness_map
@group({{MATERIAL_GROUP}}) @binding(4) var roughness_tex: texture_2d<f32>;
@group({{MATERIAL_GROUP}}) @binding(6) var roughness_sampler: sampler;
#endif
#if emissive_map
@group({{MATERIAL_GROUP}}) @binding(7) var emissive_tex: texture_2d<f32>;
@group({{MATERIAL_GROUP}}) @binding(8) var emissive_sampler: sampler;
#endif
#if occlusion_map
@group({{MATERIAL_GROUP}}) @binding(9) var occlusion_tex: texture_2d<f32>;
@group({{MATERIAL_GROUP}}) @binding(10) var occlusion_sampler: sampler;
// the ambient term's factor for this fragment (set by fs_main before shading)
var<private> ambient_occlusion: f32 = 1.0;
#endif
#if pbr
// the metallic factor of this fragment (set by fs_main before shading)
var<private> pbr_metallic: f32 = 0.0;
{{PBR_FUNCTIONS}}
#endif
#if ibl
@group({{MATERIAL_GROUP}}) @binding(11) var<storage, read> ibl_maps: array<vec4f>;
{{IBL_FUNCTIONS}}
#endif
#if clearcoat_map
@group({{MATERIAL_GROUP}}) @binding(12) var clearcoat_tex: texture_2d<f32>;
@group({{MATERIAL_GROUP}}) @binding(13) var clearcoat_sampler: sampler;
#endif
#if clearcoat_roughness_map
@group({{MATERIAL_GROUP}}) @binding(14) var clearcoat_roughness_tex: texture_2d<f32>;
@group({{MATERIAL_GROUP}}) @binding(15) var clearcoat_roughness_sampler: sampler;
#endif
#if clearcoat_normal_map
@group({{MATERIAL_GROUP}}) @binding(16) var clearcoat_normal_tex: texture_2d<f32>;
@group({{MATERIAL_GROUP}}) @binding(17) var clearcoat_normal_sampler: sampler;
#endif
#if clearcoat
{{CLEARCOAT_FUNCTIONS}}
#endif

struct VertexIn {
    @location(0) position: vec3f,
#if lighting
    @location(1) normal: vec3f,
#endif
#if uv
    @location(2) uv: vec2f,
#endif
#if tangent
    @location(3) tangent: vec4f,
#endif
#if vertex_color
    @location(4) color: vec4f,
#endif
#if uv1
    @location(5) uv1: vec2f,
#endif
#if uv2
    @location(6) uv2: vec2f,
#endif
#if uv3
    @location(7) uv3: vec2f,
#endif
#if uv4
    @location(8) uv4: vec2f,
#endif
};

struct VertexOut {
    @builtin(position) clip: vec4f,
#if lighting
    @location(0) world_position: vec3f,
    @location(1) normal: vec3f,
#endif
#if uv
    @location(2) uv: vec2f,
#endif
#if tangent
    @location(3) tangent: vec4f,
#endif
#if vertex_color
    @location(4) color: vec4f,
#endif
#if uv1
    @location(5) uv1: vec2f,
#endif
#if uv2
    @location(6) uv2: vec2f,
#endif
#if uv3
    @location(7) uv3: vec2f,
#endif
#if uv4
    @location(8) uv4: vec2f,
#endif
};

@vertex
#if instance_attributes
fn vs_main(in: VertexIn, inst: InstanceIn) -> VertexOut {
    let world = mat4x4f(inst.world0, inst.world1, inst.world2, inst.world3);
#if lighting
    let normal_matrix = mat3x3f(inst.normal0, inst.normal1, inst.normal2_mirror.xyz);
#endif
#if tangent
    let mirror = inst.normal2_mirror.w;
#endif
#else
fn vs_main(in: VertexIn, @builtin(instance_index) instance: u32) -> VertexOut {
#if culled
    let object_data = objects[visible[instance]];
#else
    let object_data = objects[instance];
#endif
    let world = object_data.world;
#if lighting
    let normal_matrix = object_data.normal;
#endif
#if tangent
    let mirror = object_data.mirror;
#endif
#endif
    var out: VertexOut;
    // Written as the tutorial's GLSL does (proj * view * model * p, evaluated left to right), so the
    // float32 arithmetic matches it operation for operation.
    out.clip = camera.proj * camera.view * world * vec4f(in.position, 1.0);
#if lighting
    out.world_position = (world * vec4f(in.position, 1.0)).xyz;
    out.normal = normal_matrix * in.normal;  // cofactor matrix: right direction, any length
#endif
#if uv
#if flip_v
    out.uv = vec2f(in.uv.x, 1.0 - in.uv.y);
#else
    out.uv = in.uv;
#endif
#endif
#if tangent
    let world3 = mat3x3f(world[0].xyz, world[1].xyz, world[2].xyz);
    out.tangent = vec4f(world3 * in.tangent.xyz, in.tangent.w * mirror);
#endif
#if vertex_color
    out.color = in.color;
#endif
#if uv1
    out.uv1 = in.uv1;
#endif
#if uv2
    out.uv2 = in.uv2;
#endif
#if uv3
    out.uv3 = in.uv3;
#endif
#if uv4
    out.uv4 = in.uv4;
#endif
    return out;
}

#if lighting
// v / |v|, or `fallback` when v is (nearly) zero or not finite.
fn safe_normalize(v: vec3f, fallback: vec3f) -> vec3f {
    let len2 = dot(v, v);
    if (len2 > 1e-20 && len2 < 1e30) {
        return v * inverseSqrt(len2);
    }
    return fallback;
}

#if tangent
// n perturbed by a tangent-space normal map's texel, its xy scaled by `strength`.
fn mapped_normal(n: vec3f, tangent: vec4f, texel: vec3f, strength: f32) -> vec3f {
    // Tangent orthogonalised against n; a degenerate tangent falls back to the unperturbed normal.
    let t_raw = tangent.xyz - n * dot(n, tangent.xyz);
    if (dot(t_raw, t_raw) <= 1e-20) {
        return n;
    }
    let t = normalize(t_raw);
    let b = select(1.0, -1.0, tangent.w < 0.0) * cross(n, t);
    var m = texel * 2.0 - 1.0;
    m = vec3f(m.xy * strength, m.z);
    return safe_normalize(t * m.x + b * m.y + n * m.z, n);
}
#endif

fn surface_normal(in: VertexOut, normal_texel: vec3f) -> vec3f {
    let n = safe_normalize(in.normal, vec3f(0.0, 0.0, 1.0));
#if normal_map
    return mapped_normal(n, in.tangent, normal_texel, material.normal_strength);
#else
    return n;
#endif
}

#if clearcoat
// The coat's own normal: the geometric one, perturbed only by the clearcoat normal map (not the base's).
fn clearcoat_normal(in: VertexOut) -> vec3f {
    let n = safe_normalize(in.normal, vec3f(0.0, 0.0, 1.0));
#if clearcoat_normal_map
    return mapped_normal(n, in.tangent, clearcoat_normal_texel, material.clearcoat_normal_scale);
#else
    return n;
#endif
}
#endif

#if !pbr
fn shininess(roughness: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    let r4 = r * r * r * r;
    return clamp(2.0 / max(r4, 1e-6) - 2.0, 1.0, 4096.0);
}

// Radiance reflected towards v from irradiance E arriving along l (all unit vectors).
fn blinn_phong(n: vec3f, l: vec3f, v: vec3f, albedo: vec3f, s: f32, irradiance: vec3f) -> vec3f {
    let n_dot_l = max(dot(n, l), 0.0);
    let h = safe_normalize(l + v, n);
    let spec = material.specular * (s + 8.0) / 8.0 * pow(max(dot(n, h), 0.0), s);
    return irradiance * n_dot_l * (albedo + vec3f(spec));
}
#endif

// A point light's range window and spot cone (KHR_lights_punctual; 1 exactly for a plain point light):
// clamp(1 - (d / range)^4, 0, 1) when range > 0, times clamp(dot(axis, -l) * scale + offset, 0, 1)^2.
fn light_window(light: PointLight, d2: f32, l: vec3f) -> f32 {
    var window = 1.0;
    if (light.position.w > 0.0) {
        let x = d2 / (light.position.w * light.position.w);
        window = clamp(1.0 - x * x, 0.0, 1.0);
    }
    let cone = clamp(dot(light.spot.xyz, -l) * light.spot.w + light.radiance.w, 0.0, 1.0);
    return window * cone * cone;
}

fn shade(albedo: vec3f, in: VertexOut, normal_texel: vec3f, roughness: f32) -> vec3f {
    let n = surface_normal(in, normal_texel);
    // eye.w = 0 for an orthographic camera (eye.xyz the direction towards it): every view vector is parallel
    let v = safe_normalize(camera.eye.xyz - in.world_position * camera.eye.w, n);
#if !pbr
    let s = shininess(roughness);
#endif
#if ibl
    var color = ibl_radiance(n, v, albedo, pbr_metallic, roughness);  // the environment replaces the ambient term
#else
    var color = camera.ambient.rgb * albedo;
#endif
#if occlusion_map
    color = color * ambient_occlusion;
#endif
#if clearcoat
    let nc = clearcoat_normal(in);
    let coat_weight = clamp(clearcoat_weight, 0.0, 1.0) * clearcoat_fresnel(nc, v);
#if ibl
    var coat = ibl_layer(nc, v, clearcoat_rough);
#else
    var coat = camera.ambient.rgb;
#endif
#if occlusion_map
    coat = coat * ambient_occlusion;
#endif
#endif
#if directional_lights
    for (var i = 0u; i < DIRECTIONAL_LIGHTS; i++) {
        let light = camera.directional[i];
        let l = safe_normalize(-light.direction.xyz, n);
#if pbr
        color += pbr_radiance(n, l, v, albedo, pbr_metallic, roughness, light.radiance.rgb);
#if clearcoat
        coat += clearcoat_radiance(nc, l, v, clearcoat_rough, light.radiance.rgb);
#endif
#else
        color += blinn_phong(n, l, v, albedo, s, light.radiance.rgb);
#endif
    }
#endif
#if point_lights
    for (var i = 0u; i < POINT_LIGHTS; i++) {
        let light = camera.point[i];
        let to_light = light.position.xyz - in.world_position;
        let d2 = max(dot(to_light, to_light), 1e-4);
        let l = safe_normalize(to_light, n);
        let irradiance = light.radiance.rgb / d2 * light_window(light, d2, l);
#if pbr
        color += pbr_radiance(n, l, v, albedo, pbr_metallic, roughness, irradiance);
#if clearcoat
        coat += clearcoat_radiance(nc, l, v, clearcoat_rough, irradiance);
#endif
#else
        color += blinn_phong(n, l, v, albedo, s, irradiance);
#endif
    }
#endif
#if clearcoat
    clearcoat_base_weight = 1.0 - coat_weight;
    color = color * clearcoat_base_weight + coat * coat_weight;
#endif
    return color;
}
#endif

#if srgb_output
// The output is a plain 8-bit format that does not encode: apply the sRGB curve here.
fn srgb_encode(c: vec3f) -> vec3f {
    let x = clamp(c, vec3f(0.0), vec3f(1.0));
    return select(1.055 * pow(x, vec3f(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3f(0.0031308));
}
#endif

@fragment
#if double_sided
fn fs_main(vertex: VertexOut, @builtin(front_facing) front_facing: bool) -> @location(0) vec4f {
    var in = vertex;
    if (!front_facing) {
        in.normal = -in.normal;  // a back face is lit as the surface's other side
    }
#else
fn fs_main(in: VertexOut) -> @location(0) vec4f {
#endif
    var base = material.base_color;
#if albedo_map
    base = base * textureSample(albedo_tex, albedo_sampler, in.{{ALBEDO_UV}});
#endif
#if vertex_color
    base = base * in.color;
#endif
#if emissive
#if emissive_map
    let emitted = material.emissive.rgb * textureSample(emissive_tex, emissive_sampler, in.{{EMISSIVE_UV}}).rgb;
#else
    let emitted = material.emissive.rgb;
#endif
#endif
#if lighting
    // Textures are sampled here, in uniform control flow (implicit derivatives), and passed down.
#if normal_map
    let normal_texel = textureSample(normal_tex, normal_sampler, in.{{NORMAL_UV}}).xyz;
#else
    let normal_texel = vec3f(0.5, 0.5, 1.0);
#endif
#if roughness_map
    let roughness_texel = textureSample(roughness_tex, roughness_sampler, in.{{ROUGHNESS_UV}});
    let roughness = material.roughness * roughness_texel.g;
#if pbr
    pbr_metallic = material.metallic * roughness_texel.b;
#endif
#else
    let roughness = material.roughness;
#if pbr
    pbr_metallic = material.metallic;
#endif
#endif
#if occlusion_map
    let occlusion_texel = textureSample(occlusion_tex, occlusion_sampler, in.{{OCCLUSION_UV}}).r;
    ambient_occlusion = 1.0 + material.occlusion_strength * (occlusion_texel - 1.0);
#endif
#if clearcoat
    clearcoat_weight = material.clearcoat;
    clearcoat_rough = material.clearcoat_roughness;
#if clearcoat_map
    clearcoat_weight = clearcoat_weight * textureSample(clearcoat_tex, clearcoat_sampler, in.{{CLEARCOAT_UV}}).r;
#endif
#if clearcoat_roughness_map
    clearcoat_rough = clearcoat_rough * textureSample(clearcoat_roughness_tex, clearcoat_roughness_sampler,
                                                      in.{{CLEARCOAT_ROUGHNESS_UV}}).g;
#endif
#if clearcoat_normal_map
    clearcoat_normal_texel = textureSample(clearcoat_normal_tex, clearcoat_normal_sampler,
                                           in.{{CLEARCOAT_NORMAL_UV}}).xyz;
#endif
#endif
    var color = shade(base.rgb, in, normal_texel, roughness);
#else
    var color = base.rgb;
#endif
#if emissive
#if clearcoat
    color = color + emitted * clearcoat_base_weight;  // the coat lies over the emission too
#else
    color = color + emitted;
#endif
#endif
#if alpha_mask
    if (base.a < material.alpha_cutoff) {
        discard;
    }
    base.a = 1.0;  // glTF MASK: what is kept is opaque
#endif
#if opaque_alpha
    base.a = 1.0;  // glTF OPAQUE: the alpha channel is ignored
#endif
#if srgb_output
    return vec4f(srgb_encode(color), base.a);
#else
    return vec4f(color, base.a);
#endif
}
