"""The WGSL of FXAA split over an edge list (issue 31.6): the run by wgpurender/bench/fxaa_variants/edge_list.py.

FXAA's edge search (up to 24 bilinear samples) runs for only ~3% of a 4K frame's pixels, but a warp (32
invocations) with one edge pixel runs it whole while its other lanes wait: 12.5% of the warps of an 8x8 x2
dispatch hold one (benchmarks/fxaa_edge_share.py). So the pass becomes three dispatches in one compute pass:

- ``cs_mark`` over every pixel (the pass's shape): FXAA's local-contrast test (``is_edge``, as ``fxaa_at``
  does it); a pixel off edges is written at once as ``fxaa_at`` returns it there (its texel) through the rest
  of the pass (``pass_tail``: the vignette); an edge pixel is appended to the list ``edges`` (x | y << 16).
  Each workgroup counts its edges in workgroup memory and takes its slots with ONE global atomicAdd;
- ``cs_size``, one invocation: the indirect dispatch's workgroup counts from the list's length, which it moves
  to ``listed`` and zeroes for the next frame (so nothing is cleared from the CPU);
- ``cs_edges``, dispatched indirectly over the list: ``pass_color`` (``fxaa_at`` whole, then the tail) for
  the listed pixels only, 64 to a workgroup.

Every pixel is written once, by the same functions on the same texels as the one-dispatch pass: the image is
that pass's, byte for byte (tests/test_post_edge_list.py). Measured on the H100 it loses (core/plan/dispatch.py):
``cs_mark`` alone costs almost what the one dispatch does, so the plan never draws it; ``bench post-roofline
--shapes`` and benchmarks/post_interleave.py time it.
"""

from __future__ import annotations

from wgpurender.core.plan import PostPass
from wgpurender.wgpu_path.post.shaders import Shape, head_arg, pass_functions, shape_of

EDGE_GROUP = 64  # invocations per workgroup of cs_edges: one listed pixel each
MAX_GROUPS = 65535  # WebGPU's maxComputeWorkgroupsPerDimension (default): cs_size spills into y beyond it

LIST_BINDINGS = """
struct EdgeCount {
    next: atomic<u32>,  // cs_mark appends at next; cs_size moves it to listed and zeroes it
    listed: u32,        // the list's length, for cs_edges
};

@group(0) @binding(3) var dst: texture_storage_2d<FORMAT, write>;
@group(0) @binding(4) var<storage, read_write> edge_count: EdgeCount;
@group(0) @binding(5) var<storage, read_write> edges: array<u32>;
"""

MARK_MAIN = """
var<workgroup> group_edges: atomic<u32>;  // this workgroup's edge pixels, counted, then its first slot
var<workgroup> group_base: u32;

@compute @workgroup_size(WX, WY)
fn cs_mark(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) index: u32) {
    if index == 0u {
        atomicStore(&group_edges, 0u);  // zeroed here: on lavapipe the count began at a stale value without it
    }
    workgroupBarrier();
    let size = textureDimensions(src);
    var mine = 0u;  // bit k: row k's pixel is an edge
    for (var k = 0u; k < ROWSu; k++) {
        let xy = vec2u(id.x, id.y * ROWSu + k);
        if xy.x < size.x && xy.y < size.y {
            let p = vec2i(xy);
            let centre = fxaa_texel(p);
            if is_edge(luma_of(centre.rgb), luma_at(p + vec2i(0, -1)), luma_at(p + vec2i(0, 1)),
                       luma_at(p + vec2i(-1, 0)), luma_at(p + vec2i(1, 0)) HEAD_ARG) {
                mine |= 1u << k;
            } else {
                textureStore(dst, p, pass_tail(centre, vec2f(xy) + vec2f(0.5), vec2f(size)));
            }
        }
    }
    var slot = atomicAdd(&group_edges, countOneBits(mine));
    workgroupBarrier();
    if index == 0u {
        group_base = atomicAdd(&edge_count.next, atomicLoad(&group_edges));
    }
    let base = workgroupUniformLoad(&group_base);
    for (var k = 0u; k < ROWSu; k++) {
        if (mine & (1u << k)) != 0u {
            edges[base + slot] = id.x | ((id.y * ROWSu + k) << 16u);
            slot += 1u;
        }
    }
}

@compute @workgroup_size(GROUP)
fn cs_edges(@builtin(workgroup_id) group: vec3u, @builtin(num_workgroups) groups: vec3u,
            @builtin(local_invocation_index) index: u32) {
    let i = (group.y * groups.x + group.x) * GROUPu + index;
    if i < edge_count.listed {
        let xy = vec2u(edges[i] & 0xffffu, edges[i] >> 16u);
        let p = vec2i(xy);
        textureStore(dst, p, pass_color(p, vec2f(xy) + vec2f(0.5), vec2f(textureDimensions(src))));
    }
}
"""

SIZE_WGSL = """
struct EdgeCount {
    next: u32,
    listed: u32,
};

@group(0) @binding(0) var<storage, read_write> edge_count: EdgeCount;
@group(0) @binding(1) var<storage, read_write> args: array<u32, 3>;  // cs_edges' indirect dispatch

@compute @workgroup_size(1)
fn cs_size() {
    let n = edge_count.next;
    let groups = (n + GROUPu - 1u) / GROUPu;
    args[0] = min(groups, MAXu);
    args[1] = (groups + MAXu - 1u) / MAXu;
    args[2] = 1u;
    edge_count.listed = n;
    edge_count.next = 0u;
}
""".replace("GROUP", str(EDGE_GROUP)).replace("MAX", str(MAX_GROUPS))


def edge_list_source(p: PostPass, shape: Shape | None = None) -> str:
    """cs_mark and cs_edges for an FXAA pass (its effects untiled, its shape the plan's unless given)."""
    wx, wy, rows = shape_of(p, shape)
    main = ((LIST_BINDINGS + MARK_MAIN).replace("FORMAT", p.output_format).replace("HEAD_ARG", head_arg(p))
            .replace("WX", str(wx)).replace("WY", str(wy)).replace("ROWS", str(rows))
            .replace("GROUP", str(EDGE_GROUP)))
    return "\n\n".join([*pass_functions(p, shape, ""), main]) + "\n"

