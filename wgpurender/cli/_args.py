"""Arguments that several subcommands share."""

from __future__ import annotations

import argparse
import math


def size_arg(text: str) -> tuple[int, int]:
    """Parse WxH, e.g. 800x600."""
    parts = text.lower().split("x")
    try:
        width, height = (int(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"malformed size {text!r}: expected WIDTHxHEIGHT, e.g. 800x600") from None
    if not (0 < width <= 16384 and 0 < height <= 16384):
        raise argparse.ArgumentTypeError(f"size {text!r} out of range: width and height must be 1..16384")
    return width, height


def finite_float(text: str) -> float:
    """A finite number (not nan, inf or -inf)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number: give a plain number such as 1.5")
    return value


def positive_float(text: str) -> float:
    """A finite number above 0."""
    value = finite_float(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be above 0, e.g. 32")
    return value


def add_backend_arg(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--backend",
        default=None,
        help="graphics backend: vulkan (default), opengl, metal, d3d12 or auto (the best adapter of any); "
             "also $WGPURENDER_BACKEND",
    )


def add_anisotropy_arg(parser: argparse.ArgumentParser) -> None:
    """--anisotropy, with the same choices and default on every command that draws a scene."""
    from wgpurender.core.anisotropy import ANISOTROPY_HELP, ANISOTROPY_RULES, DEFAULT_ANISOTROPY

    parser.add_argument("--anisotropy", choices=ANISOTROPY_RULES, default=DEFAULT_ANISOTROPY, help=ANISOTROPY_HELP)


def add_render_args(parser: argparse.ArgumentParser) -> None:
    """--size, --msaa, --format, --time: how a stage or scene is rendered."""
    parser.add_argument("--size", type=size_arg, default=None, metavar="WxH", help="image size (default 800x600)")
    parser.add_argument(
        "--msaa", type=int, default=None, metavar="N", help="MSAA sample count, 1 or 4 (default: the stage's)"
    )
    parser.add_argument(
        "--format",
        default=None,
        metavar="F",
        help="colour format: rgba8unorm, rgba8unorm-srgb (default) or rgba16float",
    )
    parser.add_argument(
        "--time",
        type=finite_float,
        default=0.0,
        metavar="T",
        help="animation time in seconds, fixed so output is deterministic (default 0)",
    )
    add_backend_arg(parser)
