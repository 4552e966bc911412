// Many objects animated and culled on the GPU (wgpurender/bench/objects_gpu.py), variant flags:
//   cull  the compute pass: each object's position at time t (the same drift as bench/objects.py's
//         object_data), tested against the view box; the visible ones are appended to a list and
//         counted into the indirect draw's instance count;
//   draw  the render pass: one indirect draw of a quad per visible object, the object recomputed from
//         its index. Later objects must cover earlier ones whatever order the list has: depth says so.
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
