"""FXAA with its luma in the intermediate's alpha (FXAA 3.11's own layout; issue 31.6), a benchmark variant.

FXAA's contrast test is most of its pass (docs/perf-h100/2026-11-27-post5/): five texel loads and five square
roots a pixel. Here the pass before FXAA (memory bound: a square root there costs nothing) stores each pixel's
FXAA luma in alpha, computed from the colour as the intermediate STORES it (rgb rounded to f16 first), and FXAA
reads the lumas of N, W, NW (and M) with one ``textureGather`` of alpha at the pixel's top-left corner and S, E,
SE with one at its bottom-right, plus the centre texel; NE and SW only on edge pixels. The edge search still
takes the luma of its bilinear samples' colour, as the plan's pass does.

What it costs: the intermediate's alpha. The chain's output alpha is the scene's (tonemap, FXAA and vignette
pass it through): 1 unless ``render.clear_color`` has an alpha below 1 or a material blends or writes one, and
an offscreen render keeps it in its PNG. This variant writes alpha 1, so it is for outputs whose alpha is known
to be 1 only (tests/test_post_luma_alpha.py; benchmarks/post_interleave.py --set gather compares the images).
A first version that fed the f16 lumas straight into all of FXAA's arithmetic (no exact recompute) changed
pixels of final.toml on lavapipe, by many steps at some: the edge search's end test is sensitive to the last bits.
Measured on the H100 (docs/perf-h100/2026-11-27-post6/): byte-equal, and only 2-3% faster than the plan's pass.

The WGSL is the plan's text for each pass with a few lines exchanged; each exchange must match exactly once, so a
change of shaders_wgsl/post_fxaa.wgsl that this does not follow fails here, not silently.
"""

from __future__ import annotations

import wgpu

from wgpurender.core.plan import PostPass
from wgpurender.wgpu_path.post.passes import ComputePass
from wgpurender.wgpu_path.post.shaders import pass_source

STORED_LUMA = """
// FXAA's luma (post_fxaa.wgsl's luma_of) of the colour as an f16 texture stores it: each channel rounded to f16
// first, so FXAA's luma is of the very texel values it would read.
fn stored_luma(c: vec3f) -> f32 {
    let rg = unpack2x16float(pack2x16float(c.rg));
    let b = unpack2x16float(pack2x16float(vec2f(c.b, 0.0))).x;
    return sqrt(max(dot(vec3f(rg, b), LUMA_709), 0.0));
}
"""

TAIL_END = "    return c;\n}\n\nfn pass_color("
TAIL_WITH_LUMA = "    return vec4f(c.rgb, stored_luma(c.rgb));\n}\n\nfn pass_color("

CONTRAST_READS = """    // 1. local contrast (texture y grows downwards: north is -y)
    let l_m = luma_of(centre.rgb);
"""
# textureGather at a texel corner returns the 2x2 texels around it: x (left, below), y (right, below),
# z (right, above), w (left, above); clamp-to-edge as src_clamped clamps. A stored luma s is the exact luma l
# rounded to f16 (to nearest or towards zero: |s - l| <= l / 1024), of rgb rounded once more by pack2x16float
# (at most as much again): |s - l| < l / 512 <= s_max / 256 + 2^-20 (``slack``, twice that bound, subnormals
# included). If the contrast test fails by more than that on the stored lumas, it fails on the exact ones: the
# pixel is returned as the plan's pass returns it. Otherwise (the edges and a few pixels near the threshold) the
# exact lumas are computed from the texels, as the plan's pass does, so every decision is the plan's.
PREFILTER = """    // 1a. the contrast test on the stored lumas, with slack for their f16 rounding (luma_alpha.py)
    let g_tl = textureGather(3, src, src_sampler, uv - 0.5 * inv);  // x W, y M, z N, w NW
    let g_br = textureGather(3, src, src_sampler, uv + 0.5 * inv);  // x S, y SE, z E, w M
    let s_max = max(centre.a, max(max(g_tl.z, g_br.x), max(g_tl.x, g_br.z)));
    let s_min = min(centre.a, min(min(g_tl.z, g_br.x), min(g_tl.x, g_br.z)));
    let slack = s_max * (1.0 / 256.0) + (1.0 / 1048576.0);
    if s_max - s_min + 2.0 * slack < max(params.edge_threshold_min, (s_max - slack) * params.edge_threshold) {
        return vec4f(centre.rgb, 1.0);
    }
"""
FXAA_EXCHANGES = (
    (CONTRAST_READS, PREFILTER + CONTRAST_READS),
    ("        return centre;\n", "        return vec4f(centre.rgb, 1.0);\n"),
    ("    return vec4f(color.rgb, centre.a);\n", "    return vec4f(color.rgb, 1.0);\n"),
)


def exchange(text: str, old: str, new: str) -> str:
    """``text`` with ``old`` replaced by ``new``; ``old`` must occur exactly once."""
    if text.count(old) != 1:
        raise ValueError(f"luma in alpha: expected one {old.strip().splitlines()[0]!r} in the pass's WGSL, found "
                         f"{text.count(old)}")
    return text.replace(old, new)


def tonemap_luma_source(p: PostPass, shape: tuple[int, int, int] | None = None) -> str:
    """The per-pixel pass before FXAA, its alpha replaced by the stored colour's FXAA luma."""
    if p.path != "compute" or not all(s.spec.fusable for s in p.steps):
        raise ValueError(f"post pass {p.effect!r}: luma in alpha is written by a per-pixel compute pass")
    return exchange(pass_source(p, shape, ""), TAIL_END, TAIL_WITH_LUMA) + STORED_LUMA


def fxaa_gather_source(p: PostPass, shape: tuple[int, int, int] | None = None) -> str:
    """FXAA's pass (untiled, reading a stored image) taking its lumas from alpha, writing alpha 1."""
    if p.path != "compute" or p.prelude or p.steps[0].effect != "fxaa":
        raise ValueError(f"post pass {p.effect!r}: luma in alpha is read by an FXAA compute pass over a stored image")
    text = pass_source(p, shape, "")
    for old, new in FXAA_EXCHANGES:
        text = exchange(text, old, new)
    return text


class LumaAlphaPass(ComputePass):
    """A planned compute pass drawn as its luma-in-alpha variant: ``role`` "tonemap" (writes the lumas) or
    "fxaa" (reads them)."""

    def __init__(self, device: wgpu.GPUDevice, p: PostPass, role: str,
                 shape: tuple[int, int, int] | None = None) -> None:
        if role not in ("tonemap", "fxaa"):
            raise ValueError(f"luma in alpha: role {role!r} is not 'tonemap' or 'fxaa'")
        self.role = role
        super().__init__(device, p, shape, "")

    def make_source(self, p: PostPass, shape, tiled) -> str:
        return (tonemap_luma_source if self.role == "tonemap" else fxaa_gather_source)(p, shape)


def draw_chain(ctx, renderer, target: wgpu.GPUTexture) -> wgpu.GPUTexture:
    """After a frame of ``renderer``'s plan (a SceneRenderer's: tonemap, then an FXAA pass) was drawn into ``target``,
    its post chain drawn again as the luma-in-alpha variant into ``target`` from the scene image that frame left;
    the variant's intermediate is a new texture. Returns it (readable: a benchmark times the passes from it, the
    tests read it back)."""
    first, second = renderer.plan.post_passes
    textures = {**renderer.attachments, "output": target}
    like = textures[first.output]
    middle = ctx.device.create_texture(label="post-luma-alpha", size=like.size, format=like.format,
                                       usage=like.usage | wgpu.TextureUsage.COPY_SRC)
    encoder = ctx.device.create_command_encoder()
    LumaAlphaPass(ctx.device, first, "tonemap").encode(encoder, textures[first.input], middle)
    LumaAlphaPass(ctx.device, second, "fxaa").encode(encoder, middle, target)
    ctx.queue.submit([encoder.finish()])
    return middle


__all__ = ["LumaAlphaPass", "draw_chain", "fxaa_gather_source", "tonemap_luma_source"]
