// Many objects animated and culled on the GPU (wgpurender/bench/objects_gpu.py), variant flags:
//   cull  the compute pass: each object's position at time t (the same drift as bench/objects.py's
//         object_data), tested against the view box; the visible ones are appended to a list and
//         counted into the indirect draw's instance count;
//   draw  the render pass: one indirect draw of a quad per visible object, the object recomputed from
//         its index. Later objects must cover earlier ones whatever order the list has: depth says so;
//   splat the compute rasteriser for quads of a few pixels: cs_splat writes each visible object's index + 1
//         into every pixel whose centre it covers (atomicMax: the later object wins, as in draw order),
//         cs_resolve turns the indices into colours and clears them for the next frame.
// The CPU writes only Params (32 bytes) per frame.

struct Params {
    view: vec4f,       // offset x, y (NDC), zoom, t (seconds)
    half_size: vec2f,  // half width, half height of every quad (NDC, before the zoom)
    count: u32,
    row: u32,          // invocations per row of the 2D dispatch (workgroups in x * 256)
};

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> centres: array<vec2f>;
@group(0) @binding(2) var<storage, read> phase_color: array<vec2u>;  // (bitcast phase, rgba8 colour)

fn centre_at(i: u32) -> vec2f {
    let a = params.view.w + bitcast<f32>(phase_color[i].x);
    let c = centres[i] + 0.01 * vec2f(sin(a), cos(a));
    return (c - params.view.xy) * params.view.z;
}

#if cull
struct DrawIndirect {
    vertex_count: u32,
    instance_count: atomic<u32>,
    first_vertex: u32,
    first_instance: u32,
};
@group(0) @binding(3) var<storage, read_write> visible: array<u32>;
@group(0) @binding(4) var<storage, read_write> draw: DrawIndirect;

@compute @workgroup_size(256)
fn cs_cull(@builtin(global_invocation_id) id: vec3u) {
    let i = id.x + id.y * params.row;
    if (i >= params.count) {
        return;
    }
    let h = params.half_size * params.view.z;
    if (any(abs(centre_at(i)) - h >= vec2f(1.0))) {
        return;  // wholly outside the view box [-1, 1]^2
    }
    visible[atomicAdd(&draw.instance_count, 1u)] = i;
}
#endif

#if draw
@group(0) @binding(3) var<storage, read> visible: array<u32>;

struct VsOut {
    @builtin(position) position: vec4f,
    @location(0) color: vec4f,
};

@vertex
fn vs_main(@builtin(vertex_index) v: u32, @builtin(instance_index) k: u32) -> VsOut {
    let i = visible[k];
    let corner = vec2f(f32(v & 1u) * 2.0 - 1.0, f32((v >> 1u) & 1u) * 2.0 - 1.0);
    var out: VsOut;
    let depth = 1.0 - f32(i + 1u) / f32(params.count + 1u);  // later objects nearer ("less" wins)
    out.position = vec4f(centre_at(i) + corner * params.half_size * params.view.z, depth, 1.0);
    out.color = unpack4x8unorm(phase_color[i].y);
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4f {
    return in.color;
}
#endif

#if splat
@group(0) @binding(3) var<storage, read_write> ids: array<atomic<u32>>;
@group(0) @binding(4) var dst: texture_storage_2d<rgba8unorm, write>;

const MAX_SPAN: i32 = 64;  // pixels per side a quad may cover here (the bench's are 4x4 at 800x600)

@compute @workgroup_size(256)
fn cs_splat(@builtin(global_invocation_id) id: vec3u) {
    let i = id.x + id.y * params.row;
    if (i >= params.count) {
        return;
    }
    let c = centre_at(i);
    let h = params.half_size * params.view.z;
    if (any(abs(c) - h >= vec2f(1.0))) {
        return;
    }
    let size = vec2f(textureDimensions(dst));
    // pixel centres strictly inside the rectangle: x_ndc = (px + 0.5) / w * 2 - 1, y_ndc = 1 - (py + 0.5) / h * 2
    let lo = vec2f((c.x - h.x + 1.0) * 0.5 * size.x - 0.5, (1.0 - (c.y + h.y)) * 0.5 * size.y - 0.5);
    let hi = vec2f((c.x + h.x + 1.0) * 0.5 * size.x - 0.5, (1.0 - (c.y - h.y)) * 0.5 * size.y - 0.5);
    let p0 = max(vec2i(floor(lo)) + 1, vec2i(0));
    let p1 = min(vec2i(ceil(hi)) - 1, vec2i(size) - 1);
    let w = i32(size.x);
    for (var y = p0.y; y <= min(p1.y, p0.y + MAX_SPAN); y++) {
        for (var x = p0.x; x <= min(p1.x, p0.x + MAX_SPAN); x++) {
            atomicMax(&ids[y * w + x], i + 1u);
        }
    }
}

@compute @workgroup_size(16, 16)
fn cs_resolve(@builtin(global_invocation_id) id: vec3u) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let k = atomicExchange(&ids[id.y * size.x + id.x], 0u);  // read, and clear for the next frame
    var color = vec4f(0.0, 0.0, 0.0, 1.0);
    if (k > 0u) {
        color = unpack4x8unorm(phase_color[k - 1u].y);
    }
    textureStore(dst, vec2i(id.xy), color);
}
#endif
