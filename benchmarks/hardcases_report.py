"""Print the measured numbers behind tests/hardcases on this machine's GPU (for docs/numerics.md's columns).

Usage: python benchmarks/hardcases_report.py [--backend Vulkan]
Reuses the test modules' scenes and helpers, so the numbers are those the tests assert on.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "tests"), str(ROOT / "tests" / "hardcases")]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--backend", default="Vulkan")
    args = parser.parse_args()

    import test_degenerate as deg
    import test_far_from_origin as far
    import test_hdr_extremes as hdr
    import test_msaa_slivers as msaa
    import test_scale_normals as sn
    import test_uv_tiling as uvt
    from numerics.camera_relative import camera_relative, model_view
    from numerics.coverage import cell_sums, render_coverage, triangle_areas
    from numerics.depth_planes import render_planes, wrong_pixels
    from numerics.normals import analytic_normals
    from numerics.uv_tiling import exact_uvs, wrap_uvs

    from wgpurender.core.view import transforms as T
    from wgpurender.wgpu_path.device.context import get_context

    ctx = get_context(args.backend)
    print(f"adapter: {ctx.describe()}")

    print("\n[depth precision] wrong pixels of 4096, far plane drawn first")
    for fmt, rz in (("depth24plus", False), ("depth32float", False), ("depth24plus", True), ("depth32float", True)):
        n = wrong_pixels(render_planes(ctx, (64, 64), depth_format=fmt, reverse_z=rz, near_first=False))
        print(f"  {fmt:13s} reverse_z={rz!s:5s}: {n}")

    print("\n[far from origin] max screen error, px")
    print(f"  naive float32 world, proj*view : {far._max_error(ctx, lambda v: (far.WORLD, far.PROJ @ v)):.3g}")
    composed = far._max_error(ctx, lambda v: (model_view(v, far.WORLD), far.PROJ))
    print(f"  model-view in float64          : {composed:.3g}")

    def rel(v):
        w, r = camera_relative(far.WORLD, v)
        return w, far.PROJ @ r

    print(f"  camera-relative world          : {far._max_error(ctx, rel):.3g}")

    print("\n[normals] max angle error, rad (MODE 0 ours, 1 f32 inverse-transpose, 2 world matrix)")
    for name, s in sn.SCALES.items():
        ref = analytic_normals(s, sn.R, sn._normals())
        errs = []
        for mode in (0, 1, 2):
            got = sn._gpu(ctx, sn.R @ T.scale(s), mode)
            errs.append("NaN" if not np.isfinite(got).all() else f"{sn.angle(got, ref).max():.2g}")
        print(f"  {name:24s}: " + "  ".join(errs))

    print("\n[degenerate] non-finite pixels (safe / plain normalize)")
    bad = [(~np.isfinite(deg._render(ctx, safe))).any(axis=-1).sum() for safe in (True, False)]
    print(f"  {bad[0]} / {bad[1]} of 4096")

    print("\n[uv tiling] max texel-coordinate error, share of wrong nearest fetches")
    uv = exact_uvs(uvt.SIZE, uvt.CORNERS)
    texel = (uv - np.floor(uv)) * uvt.TEX
    reference = (texel, np.floor(texel), np.abs(texel - np.round(texel)).min(axis=-1))
    for name, corners in (("naive raw", uvt.CORNERS.astype(np.float32)), ("wrapped", wrap_uvs(uvt.CORNERS))):
        err, wrong, _ = uvt._errors(ctx, corners, reference)
        print(f"  {name:10s}: {err:.3g} texel, {wrong.mean():.1%} wrong")

    print("\n[msaa slivers] relative sum error, per-triangle mean |cov - area|, share vanished")
    for name, make in msaa.SETS.items():
        tri = make()
        areas = triangle_areas(tri)
        for n in (1, 4):
            cov = cell_sums(render_coverage(ctx, msaa.SIZE, tri, n), msaa.CELL)
            print(
                f"  {name:6s} {n}x: {(cov.sum() - areas.sum()) / areas.sum():+.2%}, "
                f"{np.abs(cov - areas).mean():.3f} px^2, {(cov == 0).mean():.1%}"
            )

    print("\n[hdr extremes] non-finite outputs, min output for radiance >= 100 (exposure 1)")
    for fmt in ("rgba32float", "rgba16float"):
        for op in ("aces", "reinhard"):
            out = hdr._tonemap(ctx, fmt, operator=op, exposure=1.0)
            bright = np.nanmin(out[hdr.BRIGHT])
            print(f"  {fmt} {op:8s}: {(~np.isfinite(out)).sum()} non-finite, bright min {bright:.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
