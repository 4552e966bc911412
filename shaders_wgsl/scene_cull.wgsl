// GPU frustum culling of one instanced draw (wgpurender/wgpu_path/scene/culling.py; the rule in
// wgpurender/core/plan/culling.py). One invocation per instance: the mesh's bounding sphere is moved by the
// instance's world matrix and scaled by its largest axis scale; if it lies wholly outside any of the six frustum
// planes (normal pointing inwards, n.p + d >= 0 inside) the instance is dropped, else its index is appended to
// the visible list at the draw's first instance and counted into the indirect draw's instance_count (an atomic:
// the order of the list is the order the invocations finish, which changes no pixel of an opaque draw: each
// instance is depth-tested on its own).

struct Object {
    world: mat4x4f,
    rest: array<vec4f, 4>,  // normal matrix and mirror sign: the vertex shader's, not read here
};

struct Cull {
    planes: array<vec4f, 6>,
    sphere: vec4f,          // xyz: centre in model space, w: radius
    first: u32,             // the draw's first instance (its slice of objects and of visible)
    count: u32,             // its instances
    args: u32,              // the u32 index of its indirect block's instance_count
    pad: u32,
};

@group(0) @binding(0) var<storage, read> objects: array<Object>;
@group(0) @binding(1) var<storage, read_write> visible: array<u32>;
@group(0) @binding(2) var<storage, read_write> indirect: array<atomic<u32>>;
@group(0) @binding(3) var<uniform> cull: Cull;

@compute @workgroup_size(64)
fn cs_cull(@builtin(global_invocation_id) id: vec3u) {
    if (id.x >= cull.count) {
        return;
    }
    let i = cull.first + id.x;
    let w = objects[i].world;
    let centre = (w * vec4f(cull.sphere.xyz, 1.0)).xyz;
    let scale = max(length(w[0].xyz), max(length(w[1].xyz), length(w[2].xyz)));
    let radius = cull.sphere.w * scale;
    for (var p = 0u; p < 6u; p++) {
        let plane = cull.planes[p];
        if (dot(plane.xyz, centre) + plane.w < -radius) {
            return;
        }
    }
    let slot = atomicAdd(&indirect[cull.args], 1u);
    visible[cull.first + slot] = i;
}
