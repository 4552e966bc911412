"""wgpurender compare: how far apart two images are, and where."""

from __future__ import annotations

import argparse

from ._args import positive_float


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "compare",
        help="compare two PNGs: PSNR, max difference, share of pixels off, FLIP",
        description="Print PSNR, the largest channel difference, the share of pixels off by more than 1/255 "
        "and 2/255, and the mean FLIP error of B against the reference A. Exits 1 when a threshold is exceeded.",
    )
    p.add_argument("reference", metavar="A.png")
    p.add_argument("test", metavar="B.png")
    p.add_argument("--heatmap", metavar="PNG", help="write a magnified difference image")
    p.add_argument("--gain", type=positive_float, default=32.0, help="heatmap magnification (default 32)")
    p.add_argument(
        "--threshold",
        action="append",
        default=[],
        metavar="METRIC=VALUE",
        type=_threshold,
        help="fail (exit 1) when METRIC exceeds VALUE (psnr: falls below); metrics: "
        "psnr, max_abs, over_1, over_2, flip_mean; repeatable. Default: flip_mean=0.005",
    )
    p.set_defaults(func=run)


def _threshold(text: str) -> tuple[str, float]:
    from ..compare import METRICS

    name, _, value = text.partition("=")
    if name not in METRICS:
        raise argparse.ArgumentTypeError(f"unknown metric {name!r}: choose from {', '.join(METRICS)}")
    try:
        return name, float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"threshold {text!r} needs a number after '='") from None


def run(args) -> int:
    from ..compare import compare_images, heatmap
    from ..imageio import check_writable, load_png, save_png

    if args.heatmap:
        check_writable(args.heatmap)
    a, b = load_png(args.reference), load_png(args.test)
    result = compare_images(a, b)
    for name, value in result.as_dict().items():
        print(f"{name:>10}: {value:.6g}")
    if args.heatmap:
        print(f"heatmap: {save_png(args.heatmap, heatmap(a, b, args.gain))}")
    failed = []
    for name, limit in args.threshold or [("flip_mean", 0.005)]:
        value = getattr(result, name)
        if (value < limit) if name == "psnr" else (value > limit):
            failed.append(f"{name} {value:.6g} {'<' if name == 'psnr' else '>'} {limit:g}")
    if failed:
        print("over threshold: " + "; ".join(failed))
        return 1
    return 0
