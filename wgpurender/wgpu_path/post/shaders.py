"""The WGSL of one post pass, generated from the plan: parameter structs, the composed effects, an entry point.

Each effect's file (shaders_wgsl/post_<name>.wgsl) holds only functions: a per-pixel effect
``<name>_pixel(texel, pos, size, params) -> vec4f``, a neighbourhood effect ``<name>_at(p, pos, params)``
(FXAA also ``fxaa_marks(p, params) -> bool`` for its mask). Their parameter structs are generated here
from the GPU-free specs (wgpurender/core/course/effects.py) with :mod:`wgpurender.core.shaders.uniforms`, like the
scene's structs, so Python and WGSL cannot disagree on a field (a choice parameter is ``<name>_index``).

A pass's shader is post_common.wgsl, the structs, ``struct PassParams { s0: ..., s1: ... }`` (one member
per step that has parameters), the effects' functions, and a generated ``pass_color``: the first step's
colour (the texel itself, or the neighbourhood effect's result) passed through every per-pixel step in
order. That composition is what fuses a chain: the steps are functions in registers, so the image is
read once and written once. The entry points around ``pass_color``:

- fragment: ``fs_main`` (a full-screen triangle) and, for an effect with a mask (FXAA on lavapipe),
  ``fs_mark``: llvmpipe runs both sides of a branch for every pixel, so FXAA's early exit saved nothing
  (a flat image cost as much as the scene); what it does skip is a block of pixels failing an early
  depth test. ``fs_mark`` writes every pixel as it is off edges and depth 1 on edge pixels, 0 elsewhere;
  ``fs_main`` (depth 0, compare "less") then runs only on edge blocks. Bit-identical to one draw;
- compute: ``cs_main`` over workgroups of the pass's shape (the plan's, core/plan/dispatch.py), ``textureStore``
  into ``dst`` (binding 3), a storage texture. A tiled FXAA pass (the plan's ``tile``: "texels" with a prelude,
  knob post_intermediate = none) first fills a workgroup tile and a one-texel apron in workgroup memory with
  ``tile_source``: the effects before FXAA recomputed once per texel instead of at each read (a benchmark may
  also tile the plain FXAA pass, with texels or with their lumas: wgpu_path/post/tiles.py). Reads that fall in
  the tile take it, the rest call ``tile_source`` itself: the same function on the same texel, so the image is
  the untiled one's.
  A pass whose output is an ``-srgb`` format writes ``rgba8unorm`` instead (``-srgb`` cannot be a storage
  texture) with the sRGB curve applied here: offscreen, the output texture itself is that rgba8unorm twin
  (same bytes, read back as they are); into a swapchain image a scratch, which the runner then copies.
"""

from __future__ import annotations

from wgpurender.core.course.effects import EffectSpec, encoding_of, needs_shader_encoding
from wgpurender.core.plan import PostPass
from wgpurender.core.plan.dispatch import TILE_KINDS
from wgpurender.core.plan.post import RECOMPUTING_READERS
from wgpurender.core.shaders.uniforms import F32, Struct, wgsl_structs
from wgpurender.wgpu_path.device.shaders import load_wgsl
from wgpurender.wgpu_path.post.tiles import tiled_main, tiled_reads

COMMON_WGSL = "post_common.wgsl"
SRGB_WGSL = "post_srgb.wgsl"
# The compute path's dispatch shape is the plan's, per pass (PostPass.shape, wgpurender/core/plan/dispatch.py, where
# the H100's measurements are); ``shape`` arguments below override it (`wgpurender bench post-roofline --shapes`).
Shape = tuple[int, int, int]


def shape_of(p: PostPass, shape: Shape | None = None) -> Shape:
    """The pass's dispatch shape: ``shape`` when a benchmark sweeps it, else the plan's."""
    chosen = shape or p.shape
    if chosen is None:
        raise ValueError(f"post pass {p.effect!r} on the {p.path} path has no dispatch shape in its plan")
    return chosen


def dispatch_groups(size: tuple[int, int], shape: Shape) -> tuple[int, int]:
    """Workgroups (x, y) covering an image of ``size`` with ``shape``."""
    wx, wy, rows = shape
    return -(-size[0] // wx), -(-size[1] // (wy * rows))


def params_struct(spec: EffectSpec) -> Struct | None:
    """The effect's parameter struct (one f32 per parameter, in spec order); None without parameters."""
    if not spec.params:
        return None
    return Struct(spec.struct_name, [(p.field, F32) for p in spec.params])


def pass_struct(p: PostPass) -> Struct | None:
    """``PassParams``: member ``s<i>`` holds step i's parameters (steps without any have no member)."""
    fields = [(f"s{i}", params_struct(s.spec)) for i, s in enumerate(p.steps) if s.spec.params]
    return Struct("PassParams", fields) if fields else None


def pack_pass(p: PostPass) -> bytes:
    struct = pass_struct(p)
    values = {f"s{i}": s.packed() for i, s in enumerate(p.steps) if s.spec.params}
    return struct.pack(values) if struct is not None else b""


def srgb_constant(p: PostPass) -> float:
    """SRGB_ENCODE of the srgb step: 1 where the format written does not encode by itself."""
    return 1.0 if needs_shader_encoding(p.output_format) else 0.0


def _arg(p: PostPass, i: int) -> str:
    return f", params.s{i}" if p.steps[i].spec.params else ""


def _tail(p: PostPass, first: int) -> str:
    lines = ["fn pass_tail(c0: vec4f, pos: vec2f, size: vec2f) -> vec4f {", "    var c = c0;"]
    for i in range(first, len(p.steps)):
        name = p.steps[i].effect
        lines.append(f"    c = {name}_pixel(c, pos, size{_arg(p, i)});")
    if encoding_of(p.encodes_for or "") == "hardware" and p.steps[-1].effect != "srgb":
        # compute into an rgba8unorm scratch or twin of an -srgb output: the hardware would have encoded, so the
        # shader does
        lines.append("    c = vec4f(srgb_encode(c.rgb), c.a);")
    lines += ["    return c;", "}"]
    return "\n".join(lines)


def _color(p: PostPass) -> str:
    h = p.prelude
    head = p.steps[h]
    first = h + 1 if not head.spec.fusable else h
    start = f"{head.effect}_at(p, pos{_arg(p, h)})" if first > h else "textureLoad(src, p, 0)"
    return (f"{_tail(p, first)}\n\n"
            f"fn pass_color(p: vec2i, pos: vec2f, size: vec2f) -> vec4f {{\n"
            f"    return pass_tail({start}, pos, size);\n}}")


STORED_TEXEL = """
fn tile_source(p: vec2i) -> vec4f {
    return src_clamped(p);
}
"""

FXAA_READS = """
fn fxaa_sample(uv: vec2f) -> vec4f {
    return textureSampleLevel(src, src_sampler, uv, 0.0);
}
"""

# post_intermediate = none: the steps before FXAA applied to each texel it reads; a bilinear tap is the mix of four
# such texels (clamp to edge, texel centres at i + 0.5), as the sampler would filter the stored image.
RECOMPUTED_TEXEL = """
fn tile_source(p: vec2i) -> vec4f {
    let size = vec2i(textureDimensions(src));
    let q = clamp(p, vec2i(0, 0), size - vec2i(1, 1));
    return pass_prelude(textureLoad(src, q, 0), vec2f(q) + vec2f(0.5), vec2f(size));
}
"""

UNTILED_TEXEL = """
fn fxaa_texel(p: vec2i) -> vec4f {
    return tile_source(p);
}

fn fxaa_luma(p: vec2i) -> f32 {
    return luma_of(fxaa_texel(p).rgb);
}
"""

FXAA_RECOMPUTED_READS = """

fn fxaa_sample(uv: vec2f) -> vec4f {
    let x = uv * vec2f(textureDimensions(src)) - vec2f(0.5);
    let i = vec2i(floor(x));
    let f = x - floor(x);
    let top = mix(fxaa_texel(i), fxaa_texel(i + vec2i(1, 0)), f.x);
    let bottom = mix(fxaa_texel(i + vec2i(0, 1)), fxaa_texel(i + vec2i(1, 1)), f.x);
    return mix(top, bottom, f.y);
}
"""


def _reads(p: PostPass, shape: Shape | None, tiled: str) -> str:
    """fxaa_texel / fxaa_luma / fxaa_sample for a pass with FXAA: ``tile_source`` (the stored image, or the prelude
    recomputed per texel), through the workgroup's ``tiled`` tile (wgpu_path/post/tiles.py) unless it is "";
    bilinear taps by the sampler, or computed from four recomputed texels."""
    texel = tiled_reads(tiled, shape_of(p, shape)) if tiled else UNTILED_TEXEL
    if p.prelude == 0:
        return STORED_TEXEL + texel + FXAA_READS
    lines = ["fn pass_prelude(c0: vec4f, pos: vec2f, size: vec2f) -> vec4f {", "    var c = c0;"]
    lines += [f"    c = {p.steps[i].effect}_pixel(c, pos, size{_arg(p, i)});" for i in range(p.prelude)]
    return "\n".join([*lines, "    return c;", "}"]) + "\n" + RECOMPUTED_TEXEL + texel + FXAA_RECOMPUTED_READS


FRAGMENT_MAIN = """
@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4f {
    return pass_color(vec2i(in.position.xy), in.position.xy, vec2f(textureDimensions(src)));
}
"""

FRAGMENT_MARK = """
struct Marked {
    @location(0) color: vec4f,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_mark(in: FullscreenOut) -> Marked {
    let p = vec2i(in.position.xy);
    let c = pass_tail(src_clamped(p), in.position.xy, vec2f(textureDimensions(src)));
    return Marked(c, select(0.0, 1.0, HEAD_marks(p ARG)));
}
"""

COMPUTE_MAIN = """
@group(0) @binding(3) var dst: texture_storage_2d<FORMAT, write>;

@compute @workgroup_size(WX, WY)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let size = textureDimensions(src);
    for (var k = 0u; k < ROWSu; k++) {
        let xy = vec2u(id.x, id.y * ROWSu + k);  // ROWS rows per invocation, neighbours in x stay neighbours
        if xy.x < size.x && xy.y < size.y {
            let p = vec2i(xy);
            textureStore(dst, p, pass_color(p, vec2f(xy) + vec2f(0.5), vec2f(size)));
        }
    }
}
"""


def _compute_main(p: PostPass, shape: Shape, tiled: str) -> str:
    if tiled:
        return tiled_main(tiled, shape, p.output_format)
    wx, wy, rows = shape
    return (COMPUTE_MAIN.replace("FORMAT", p.output_format).replace("WX", str(wx)).replace("WY", str(wy))
            .replace("ROWS", str(rows)))

def tileable(p: PostPass, kind: str = "texels") -> bool:
    """Whether the pass's reads can come through a workgroup tile of ``kind``: FXAA starts it (after its prelude),
    on the compute path; a ``luma`` tile only where FXAA reads a stored image (no prelude: a recomputing pass's
    bilinear taps need the texels themselves)."""
    if kind not in TILE_KINDS:
        raise ValueError(f"no workgroup tile {kind!r}: one of {', '.join(TILE_KINDS)}")
    fxaa = p.path == "compute" and p.steps[p.prelude].effect in RECOMPUTING_READERS
    return fxaa and (kind == "texels" or p.prelude == 0)


def pass_source(p: PostPass, shape: Shape | None = None, tiled: str | None = None) -> str:
    """The whole WGSL module of a post pass on its path (fragment or compute); ``shape``: the compute path's
    (workgroup x, workgroup y, rows per invocation), the plan's unless a benchmark sweeps it. ``tiled``: the
    plan's ``tile`` unless given: the workgroup tile FXAA on the compute path reads through ("texels" or "luma",
    wgpu_path/post/tiles.py; a benchmark may tile a pass the plan does not), or "": every texel from the texture
    or recomputed where it is read. All draw the same image."""
    tiled = p.tile if tiled is None else tiled
    if tiled and not tileable(p, tiled):
        raise ValueError(f"post pass {p.effect!r} on the {p.path} path has no FXAA reads to tile with {tiled!r}")
    parts = pass_functions(p, shape, tiled)
    if p.path == "compute":
        parts.append(_compute_main(p, shape_of(p, shape), tiled))
    else:
        parts.append(FRAGMENT_MAIN)
        if p.mask:
            parts.append(FRAGMENT_MARK.replace("HEAD", p.steps[0].effect).replace(" ARG", _arg(p, 0)))
    return "\n\n".join(parts) + "\n"


def pass_functions(p: PostPass, shape: Shape | None = None, tiled: str = "") -> list[str]:
    """The parts of a pass's WGSL before its entry points: bindings 0-2, the effects and ``pass_color`` /
    ``pass_tail`` (an FXAA pass split over two dispatches adds its own: wgpurender/bench/fxaa_variants/edge_list.py)."""
    parts = [load_wgsl(COMMON_WGSL)]
    struct = pass_struct(p)
    if struct is not None:
        parts.append(wgsl_structs(struct))
        parts.append("@group(0) @binding(2) var<uniform> params: PassParams;")
    files = dict.fromkeys(f"post_{s.effect}.wgsl" for s in p.steps)
    if p.encodes_for:  # srgb_encode, for a scratch or the twin of an -srgb output
        files.setdefault(SRGB_WGSL)
    parts.extend(load_wgsl(f) for f in files)
    if "post_fxaa.wgsl" in files:
        parts.append(_reads(p, shape, tiled))
    parts.append(_color(p))
    return parts


def head_arg(p: PostPass) -> str:
    """The parameter argument of the pass's first effect after its prelude ("" without parameters)."""
    return _arg(p, p.prelude)
