// Many-objects benchmark (wgpurender/bench/objects.py): one tiny quad per object, the per-object
// data reaching the vertex shader one of three ways, chosen by a variant flag:
//   uniform     a window into one big uniform buffer, moved per draw with a dynamic offset;
//   immediates  32 bytes of immediates (push constants) set per draw;
//   instanced   a per-instance vertex buffer, all objects in one draw.
// Render bundles replay the uniform variant's draws.

struct Object {
    rect: vec4f,   // centre x, y (NDC), half width, half height
    color: vec4f,  // linear RGBA
};

#if uniform
@group(0) @binding(0) var<uniform> object: Object;
#endif
#if immediates
var<immediate> object: Object;
#endif

struct VsOut {
    @builtin(position) position: vec4f,
    @location(0) color: vec4f,
};

// Corners of a triangle strip: (-1,-1), (1,-1), (-1,1), (1,1).
fn place(o: Object, index: u32) -> VsOut {
    let corner = vec2f(f32(index & 1u) * 2.0 - 1.0, f32((index >> 1u) & 1u) * 2.0 - 1.0);
    var out: VsOut;
    out.position = vec4f(o.rect.xy + corner * o.rect.zw, 0.0, 1.0);
    out.color = o.color;
    return out;
}

#if instanced
@vertex
fn vs_main(@builtin(vertex_index) index: u32, @location(0) rect: vec4f, @location(1) color: vec4f) -> VsOut {
    return place(Object(rect, color), index);
}
#else
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VsOut {
    return place(object, index);
}
#endif

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4f {
    return in.color;
}
