"""What the knob post_intermediate costs in accuracy: final.toml's chain (tonemap, FXAA, vignette) against float64.

The scene, the float64 truth and the error measure are tests/test_post_intermediate.py's (the truth is written in
the tests: test_post.ref_aces, fxaa_reference.fxaa, test_post.ref_vignette; nothing from the renderer). Each setting
is drawn on the wgpu path (fragment and compute) and the raw path (which refuses "none"); the error is in 8-bit
sRGB steps against the truth's round(255 * encoded): the largest, the mean, and the share of pixels off by more
than one step. The ways' differences from one another are listed too. The time each setting takes is
`bench post-roofline`'s.

    python benchmarks/post_intermediate_error.py OUT.md
"""

from __future__ import annotations

import datetime
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

import test_post_intermediate as case  # noqa: E402

from wgpurender.wgpu_path.device.context import get_context  # noqa: E402


def main(out: Path) -> int:
    ctx = get_context()
    path = case.write_scene(Path(tempfile.mkdtemp(prefix="post-intermediate-")))
    want = case.truth()
    images = {(way, knob): case.render(ctx, path, way, knob) for knob in case.KNOBS for way in case.WAYS[knob]}
    date = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [f"# post_intermediate against the float64 chain ({case.W}x{case.H})", "",
             f"- adapter: {ctx.describe()}", f"- date: {date}",
             "- command: `python benchmarks/post_intermediate_error.py OUT.md`", "",
             "| setting | way | max steps | mean steps | pixels > 1 step |", "|---|---|---:|---:|---:|"]
    for knob in case.KNOBS:
        for way in case.WAYS[knob]:
            e = case.errors(images[(way, knob)], want)
            lines.append(f"| {knob} | {way} | {e['max']:.0f} | {e['mean']:.3f} | {100 * e['over1']:.3f}% |")
    lines += ["", "| setting | ways | max difference (steps) | pixels differing by > 1 |", "|---|---|---:|---:|"]
    for knob in case.KNOBS:
        for a, b in (("compute", "fragment"), ("raw", "fragment"), ("raw", "compute")):
            if a not in case.WAYS[knob]:
                continue
            d = np.abs(images[(a, knob)] - images[(b, knob)]).max(-1)
            lines.append(f"| {knob} | {a} - {b} | {d.max():.0f} | {int((d > 1).sum())} |")
    lines += ["", *final_scene_lines(ctx)]
    text = "\n".join(lines) + "\n"
    out.write_text(text, encoding="utf-8")
    print(text, end="")
    return 0


def final_scene_lines(ctx, size: tuple[int, int] = (640, 480)) -> list[str]:
    """final.toml itself (no truth here): each setting's image against the raw path's auto image and against the
    wgpu path's auto image, both on this adapter's post path: what a change of the default would change."""
    from wgpurender.core.plan import resolve_plan
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.wgpu_path.scene import render_plan

    scene = Path(__file__).resolve().parent.parent / "assets" / "scenes" / "final.toml"
    raw = render_scene_reference(scene, size=size).astype(np.int32)
    images = {k: render_plan(ctx, resolve_plan(scene, ctx.adapter_facts(), size=size, post_intermediate=k),
                             frames=1) for k in case.KNOBS}
    path = images["auto"].plan.post_path
    lines = [f"final.toml at {size[0]}x{size[1]}, wgpu {path} path, each setting against the raw path and against "
             "the wgpu path's auto image (8-bit steps):", "",
             "| setting | vs raw: max | vs raw: pixels > 1 | vs auto: max | vs auto: pixels > 1 |",
             "|---|---:|---:|---:|---:|"]
    auto = images["auto"].pixels.astype(np.int32)
    for k, result in images.items():
        img = result.pixels.astype(np.int32)
        d_raw, d_auto = np.abs(img - raw).max(-1), np.abs(img - auto).max(-1)
        lines.append(f"| {k} | {d_raw.max()} | {int((d_raw > 1).sum())} | {d_auto.max()} | {int((d_auto > 1).sum())} |")
    return lines


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1])))
