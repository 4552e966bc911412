"""wgpurender compare: how far apart two images are, and where."""

from __future__ import annotations

import argparse

from wgpurender.cli._args import checked, gain_arg
from wgpurender.core import checks


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "compare",
        help="compare two PNGs: PSNR, max difference, share of pixels off, FLIP",
        description="Print PSNR, the largest channel difference, the share of pixels off by more than 1/255 "
        "and 2/255 (in %), and the mean FLIP error of B against the reference A. Exits 1 when a threshold is "
        "exceeded.",
    )
    p.add_argument("reference", metavar="A.png")
    p.add_argument("test", metavar="B.png")
    p.add_argument("--heatmap", metavar="PNG", help="write a magnified difference image, its colour scale below it")
    p.add_argument("--json", action="store_true",
                   help="print one JSON object instead: the metrics (shares as fractions 0..1, psnr null for "
                   "identical images), the thresholds, what failed, and the heatmap path")
    p.add_argument("--gain", type=gain_arg, default=32.0, help="heatmap magnification (default 32)")
    p.add_argument(
        "--threshold",
        action="append",
        default=[],
        metavar="METRIC=VALUE",
        type=_threshold,
        help="fail (exit 1) when METRIC exceeds VALUE (psnr: falls below); metrics: "
        "psnr, max_abs, over_1, over_2, flip_mean; shares as a fraction or a percentage (over_1=0.5%%); "
        "repeatable. Default: flip_mean=0.005",
    )
    p.set_defaults(func=run)


def _threshold(text: str) -> tuple[str, float]:
    name, equals, value = text.partition("=")
    if not equals:
        raise argparse.ArgumentTypeError(f"threshold {text!r} needs METRIC=VALUE, e.g. flip_mean=0.005")
    return checked(lambda v: checks.threshold(name, v))(value)  # checked() marks the value as CLI text


SHARES = ("over_1", "over_2")  # fractions of the pixels: printed as %


def run(args) -> int:
    from wgpurender.core.files.imageio import check_writable, image_format, load_png, save_image
    from wgpurender.core.verdict.compare import compare_images, heatmap_with_scale

    if args.heatmap:
        image_format(args.heatmap)  # the suffix picks the format; refuse an unknown one before reading
        check_writable(args.heatmap)
    a, b = load_png(args.reference), load_png(args.test)
    result = compare_images(a, b)
    heatmap_path = save_image(args.heatmap, heatmap_with_scale(a, b, args.gain)) if args.heatmap else None
    thresholds = args.threshold or [("flip_mean", 0.005)]
    failed = [(name, limit) for name, limit in thresholds if _exceeds(name, getattr(result, name), limit)]
    if args.json:
        print(_json(result, thresholds, failed, heatmap_path))
    else:
        for name, value in result.as_dict().items():
            print(f"{name:>10}: {_shown(name, value)}")
        if heatmap_path:
            print(f"heatmap: {heatmap_path}")
        if failed:
            print("over threshold: " + "; ".join(
                f"{name} {_shown(name, getattr(result, name))} {'<' if name == 'psnr' else '>'} {_shown(name, limit)}"
                for name, limit in failed))
        else:
            print("within threshold: " + "; ".join(
                f"{name} {_shown(name, getattr(result, name))} {'>=' if name == 'psnr' else '<='} "
                f"{_shown(name, limit)}" for name, limit in thresholds))
    return 1 if failed else 0


def _exceeds(name: str, value: float, limit: float) -> bool:
    return value < limit if name == "psnr" else value > limit


def _shown(name: str, value: float) -> str:
    return f"{100 * value:.4g}%" if name in SHARES else f"{value:.6g}"


def _json(result, thresholds, failed, heatmap_path) -> str:
    import json
    import math

    metrics = {k: (None if isinstance(v, float) and math.isinf(v) else v) for k, v in result.as_dict().items()}
    return json.dumps({
        "metrics": metrics,
        "thresholds": dict(thresholds),
        "failed": [name for name, _ in failed],
        "heatmap": str(heatmap_path) if heatmap_path else None,
    }, indent=2)
