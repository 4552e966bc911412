// Depth-precision scene (tests/numerics/depth_planes.py): flat-coloured squares facing the camera,
// one per instance, each from a row of `planes`: half-extent and view-space z, colour, and the
// projection (the camera sits at the origin looking down -z, so view is the identity).

struct Plane {
    clip_from_view: mat4x4f,
    color: vec4f,
    half_extent: f32,
    z: f32,
    _pad: vec2f,
};

@group(0) @binding(0) var<storage, read> planes: array<Plane>;

struct VsOut {
    @builtin(position) position: vec4f,
    @location(0) @interpolate(flat) color: vec4f,
};

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    // two triangles: corners (-1,-1) (1,-1) (1,1) / (-1,-1) (1,1) (-1,1)
    var corners = array<vec2f, 6>(vec2f(-1.0, -1.0), vec2f(1.0, -1.0), vec2f(1.0, 1.0),
                                  vec2f(-1.0, -1.0), vec2f(1.0, 1.0), vec2f(-1.0, 1.0));
    let plane = planes[ii];
    let p = vec4f(corners[vi] * plane.half_extent, plane.z, 1.0);
    var out: VsOut;
    out.position = plane.clip_from_view * p;
    out.color = plane.color;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4f {
    return in.color;
}
