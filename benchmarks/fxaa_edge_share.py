"""How many of final.toml's pixels reach FXAA's edge search, and how many warps carry one (issue 31.6).

FXAA's compute pass follows the H100's SM clock (docs/perf-h100/2026-11-27-post4/): it is bound by the SMs'
work. Most pixels leave after the local-contrast test; an edge pixel runs the edge search (up to 24 bilinear
samples). A GPU runs a warp of 32 invocations in step, so a warp with one edge pixel pays for the search on all 32
lanes. This counts, on the tone-mapped image FXAA reads (drawn here on this adapter), the edge pixels (the test of
shaders_wgsl/post_fxaa.wgsl's is_edge, in float32 numpy) and, for each dispatch shape, the share of warp steps
(32 invocations, one of their rows each) holding at least one: what a pass over edge pixels only could save.

    python benchmarks/fxaa_edge_share.py OUT.md [--size 3840x2160]
"""

from __future__ import annotations

import argparse
import datetime
import sys
from pathlib import Path

import numpy as np
import wgpu

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from wgpurender.core.plan import resolve_plan  # noqa: E402
from wgpurender.core.scene import load_scene  # noqa: E402
from wgpurender.wgpu_path.device.context import get_context  # noqa: E402
from wgpurender.wgpu_path.device.targets import read_texture  # noqa: E402

FINAL = ROOT / "assets" / "scenes" / "final.toml"
SHAPES = ((8, 8, 2), (8, 8, 1), (16, 16, 1), (32, 8, 4), (32, 8, 1))
WARP = 32
LUMA_709 = np.array([0.2126, 0.7152, 0.0722], np.float32)


def edge_mask(rgb: np.ndarray, threshold: float, threshold_min: float) -> np.ndarray:
    """FXAA's local-contrast test (clamped 4-neighbourhood of luma = sqrt(Rec. 709 luminance))."""
    lum = np.sqrt(np.maximum(rgb.astype(np.float32) @ LUMA_709, 0.0))
    pad = np.pad(lum, 1, mode="edge")
    h, w = lum.shape
    around = [pad[1 + dy:1 + dy + h, 1 + dx:1 + dx + w] for dx, dy in ((0, -1), (0, 1), (-1, 0), (1, 0))]
    l_max = np.maximum.reduce([lum, *around])
    l_min = np.minimum.reduce([lum, *around])
    return ~(l_max - l_min < np.maximum(threshold_min, l_max * threshold))


def warp_steps(edge: np.ndarray, shape: tuple[int, int, int]) -> tuple[int, int]:
    """(warp steps with an edge pixel, all warp steps) for an untiled dispatch of ``shape``: invocation (x, y)
    draws pixel rows y * rows + k, k = 0 .. rows - 1 in turn; a warp is 32 consecutive local invocation indices."""
    wx, wy, rows = shape
    h, w = edge.shape
    gx, gy = -(-w // wx), -(-h // (wy * rows))
    padded = np.zeros((gy * wy * rows, gx * wx), bool)
    padded[:h, :w] = edge
    # [group y, local y, k, group x, local x] -> [group y, group x, k, local index]
    blocks = padded.reshape(gy, wy, rows, gx, wx).transpose(0, 3, 2, 1, 4).reshape(gy, gx, rows, wy * wx)
    lanes = -(-(wy * wx) // WARP) * WARP
    blocks = np.pad(blocks, ((0, 0), (0, 0), (0, 0), (0, lanes - wy * wx)))
    warps = blocks.reshape(gy, gx, rows, lanes // WARP, WARP).any(-1)
    return int(warps.sum()), int(warps.size)


def main() -> int:
    from wgpurender.wgpu_path.scene import SceneRenderer, render_frame

    ap = argparse.ArgumentParser()
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", default="3840x2160")
    args = ap.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    ctx = get_context()
    make = ctx.device.create_texture

    def readable(**kw):  # the intermediate is not a copy source in the plan: this probe reads it back
        return make(**{**kw, "usage": kw["usage"] | wgpu.TextureUsage.COPY_SRC})

    ctx.device.create_texture = readable
    scene = load_scene(FINAL)
    plan = resolve_plan(scene, ctx.adapter_facts(), size=size, post_path="compute", post_fuse=True)
    renderer = SceneRenderer(ctx, scene, plan)
    target = renderer.create_output()
    render_frame(ctx, renderer, target)
    fxaa = next(p for p in plan.post_passes if p.steps[0].effect == "fxaa")
    params = dict(fxaa.steps[0].params)
    image = read_texture(ctx, {**renderer.attachments, "output": target}[fxaa.input])
    edge = edge_mask(image[..., :3], float(params["edge_threshold"]), float(params["edge_threshold_min"]))
    date = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [f"# FXAA's edge pixels and the warps that carry them (final.toml, {size[0]}x{size[1]})", "",
             f"- adapter: {ctx.describe()}", f"- date: {date}",
             f"- command: `python benchmarks/fxaa_edge_share.py OUT.md --size {args.size}`",
             f"- FXAA's input: {fxaa.input} ({fxaa.input_format}); "
             f"edge_threshold {params['edge_threshold']}, edge_threshold_min {params['edge_threshold_min']}",
             f"- edge pixels: {int(edge.sum())} of {edge.size} ({100 * edge.mean():.2f}%)", "",
             "| dispatch (untiled) | warp steps with an edge pixel | of all warp steps | share | "
             "edge pixels per such step (of 32) |", "|---|---:|---:|---:|---:|"]
    for shape in SHAPES:
        hit, total = warp_steps(edge, shape)
        lines.append(f"| {shape[0]}x{shape[1]} x{shape[2]} | {hit} | {total} | {100 * hit / total:.1f}% | "
                     f"{edge.sum() / hit if hit else 0:.1f} |")
    text = "\n".join(lines) + "\n"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
