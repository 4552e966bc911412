// Image-based lighting maps from an equirectangular environment (core/course/environment.py's layout), made in
// compute passes (wgpurender/wgpu_path/scene/ibl.py): the split-sum approximation of glTF's metallic-roughness BRDF
// (pbr.wgsl) under an environment.
//
// irradiance:  E(n) / pi = sum over environment texels of L * max(n.l, 0) * solid angle / pi (every texel: exact
//              for the piecewise-constant environment up to each texel's cosine taken at its centre)
// prefilter:   level k >= 1 (roughness k / (levels - 1)): the GGX-importance-sampled mean of L(l) weighted by n.l
//              with n = v = r (the split sum's assumption), `samples` Hammersley samples; level 0 (the mirror):
//              the solid-angle-weighted mean of the environment texels whose centres fall inside the texel, else
//              the texel under its centre, chosen by integer arithmetic (core/course/ibl_maps.py: mirror_level
//              says why: samples at roughness 0 land on texel corners, where float rounding picks the texel)
// brdf_lut:    (n.v, roughness) -> (A, B) with the height-correlated Smith V of pbr.wgsl: integral of f nl / F is
//              f0 A + B (Schlick F = f0 + (1 - f0)(1 - v.h)^5), importance sampled the same way

struct Params {
    env_size: vec2u,
    out_size: vec2u,
    samples: u32,
    levels: u32,
    pad0: u32,
    pad1: u32,
};

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> env: array<vec4f>;
@group(0) @binding(2) var<storage, read_write> result: array<vec4f>;

const PI: f32 = 3.14159265358979;

fn direction(uv: vec2f) -> vec3f {
    let phi = (uv.x - 0.5) * 2.0 * PI;
    let theta = uv.y * PI;
    return vec3f(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

fn env_radiance(d: vec3f) -> vec3f {
    let u = atan2(d.x, -d.z) / (2.0 * PI) + 0.5;
    let v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    let x = min(u32(max(u, 0.0) * f32(params.env_size.x)), params.env_size.x - 1u);
    let y = min(u32(max(v, 0.0) * f32(params.env_size.y)), params.env_size.y - 1u);
    return env[y * params.env_size.x + x].rgb;
}

fn hammersley(i: u32, n: u32) -> vec2f {
    return vec2f((f32(i) + 0.5) / f32(n), f32(reverseBits(i)) * 2.3283064365386963e-10);
}

// A GGX-distributed half vector around n (pdf D(h) n.h).
fn ggx_half(xi: vec2f, alpha: f32, n: vec3f) -> vec3f {
    let a2 = alpha * alpha;
    let phi = 2.0 * PI * xi.x;
    let cos_t = sqrt((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y));
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    let up = select(vec3f(1.0, 0.0, 0.0), vec3f(0.0, 0.0, 1.0), abs(n.z) < 0.999);
    let t = normalize(cross(up, n));
    let b = cross(n, t);
    return normalize(t * (sin_t * cos(phi)) + b * (sin_t * sin(phi)) + n * cos_t);
}

fn visibility(n_dot_l: f32, n_dot_v: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    return 0.5 / (n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2) + n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2));
}

@compute @workgroup_size(8, 8)
fn irradiance(@builtin(global_invocation_id) id: vec3u) {
    if (id.x >= params.out_size.x || id.y >= params.out_size.y) {
        return;
    }
    let n = direction((vec2f(id.xy) + 0.5) / vec2f(params.out_size));
    let w = params.env_size.x;
    let h = params.env_size.y;
    var sum = vec3f(0.0);
    for (var y = 0u; y < h; y++) {
        let band = 2.0 * PI / f32(w) * (cos(f32(y) / f32(h) * PI) - cos(f32(y + 1u) / f32(h) * PI));
        for (var x = 0u; x < w; x++) {
            let l = direction((vec2f(f32(x), f32(y)) + 0.5) / vec2f(f32(w), f32(h)));
            sum += env[y * w + x].rgb * max(dot(n, l), 0.0) * band;
        }
    }
    result[id.y * params.out_size.x + id.x] = vec4f(sum / PI, 1.0);
}

// The environment index (along one axis of `count` texels) whose centre falls in texel `i` of `size`: the floor of
// (i + 0.5) count / size, and the first and one past the last index whose centre (k + 0.5) / count falls inside.
fn texel_under(i: u32, size: u32, count: u32) -> u32 {
    return ((2u * i + 1u) * count) / (2u * size);
}

fn inside(k: u32, i: u32, size: u32, count: u32) -> bool {
    return ((2u * k + 1u) * size) / (2u * count) == i;
}

fn mirror_texel(texel: vec2u) -> vec3f {
    let w = params.env_size.x;
    let h = params.env_size.y;
    let size = params.out_size;
    var sum = vec3f(0.0);
    var weight = 0.0;
    for (var y = (texel.y * h) / size.y; y < min(((texel.y + 1u) * h) / size.y + 1u, h); y++) {
        if (!inside(y, texel.y, size.y, h)) {
            continue;
        }
        let band = 2.0 * PI / f32(w) * (cos(f32(y) / f32(h) * PI) - cos(f32(y + 1u) / f32(h) * PI));
        for (var x = (texel.x * w) / size.x; x < min(((texel.x + 1u) * w) / size.x + 1u, w); x++) {
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

@compute @workgroup_size(8, 8)
fn prefilter(@builtin(global_invocation_id) id: vec3u) {
    if (id.x >= params.out_size.x || id.y >= params.out_size.y || id.z >= params.levels) {
        return;
    }
    let index = (id.z * params.out_size.y + id.y) * params.out_size.x + id.x;
    if (id.z == 0u) {
        result[index] = vec4f(mirror_texel(id.xy), 1.0);
        return;
    }
    let n = direction((vec2f(id.xy) + 0.5) / vec2f(params.out_size));
    let roughness = f32(id.z) / f32(max(params.levels - 1u, 1u));
    let alpha = roughness * roughness;
    var sum = vec3f(0.0);
    var weight = 0.0;
    for (var i = 0u; i < params.samples; i++) {
        let hv = ggx_half(hammersley(i, params.samples), alpha, n);
        let l = 2.0 * dot(n, hv) * hv - n;
        let n_dot_l = dot(n, l);
        if (n_dot_l > 0.0) {
            sum += env_radiance(l) * n_dot_l;
            weight += n_dot_l;
        }
    }
    result[index] = vec4f(sum / max(weight, 1e-6), 1.0);
}

@compute @workgroup_size(8, 8)
fn brdf_lut(@builtin(global_invocation_id) id: vec3u) {
    if (id.x >= params.out_size.x || id.y >= params.out_size.y) {
        return;
    }
    let n_dot_v = (f32(id.x) + 0.5) / f32(params.out_size.x);
    let roughness = (f32(id.y) + 0.5) / f32(params.out_size.y);
    let alpha = roughness * roughness;
    let v = vec3f(sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v);
    let n = vec3f(0.0, 0.0, 1.0);
    var ab = vec2f(0.0);
    for (var i = 0u; i < params.samples; i++) {
        let hv = ggx_half(hammersley(i, params.samples), alpha, n);
        let l = 2.0 * dot(v, hv) * hv - v;
        let n_dot_l = l.z;
        let n_dot_h = max(hv.z, 1e-6);
        let v_dot_h = max(dot(v, hv), 0.0);
        if (n_dot_l > 0.0) {
            let g_vis = visibility(n_dot_l, n_dot_v, alpha) * 4.0 * n_dot_l * v_dot_h / n_dot_h;
            let fc = pow(1.0 - v_dot_h, 5.0);
            ab += vec2f((1.0 - fc) * g_vis, fc * g_vis);
        }
    }
    result[id.y * params.out_size.x + id.x] = vec4f(ab / f32(params.samples), 0.0, 1.0);
}
