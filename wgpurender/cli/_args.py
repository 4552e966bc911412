"""Arguments that several subcommands share. The checks themselves are in :mod:`wgpurender.core.checks`, which the
Python API calls too, so a mistake gets the same message from either."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any

from wgpurender.core import checks
from wgpurender.core.errors import UserError


def checked(check: Callable[[str], Any]) -> Callable[[str], Any]:
    """An argparse type from a core check: its UserError becomes argparse's one-line usage error."""

    def parse(text: str) -> Any:
        try:
            return check(checks.CliText(text))
        except UserError as err:
            raise argparse.ArgumentTypeError(str(err)) from None

    parse.__name__ = check.__name__  # argparse names the type in some messages
    return parse


size_arg = checked(checks.size)
finite_float = checked(lambda text: checks.number(text, "the value"))
gain_arg = checked(checks.gain)
time_arg = checked(checks.time)
msaa_arg = checked(checks.msaa)
format_arg = checked(checks.output_format)
backend_arg = checked(checks.backend)


def positive_float(text: str) -> float:
    """A finite number above 0."""
    return checked(lambda t: checks.positive(t, "the value"))(text)


def add_backend_arg(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--backend",
        type=backend_arg,
        default=None,
        help="graphics backend: vulkan (default), opengl, metal, d3d12 or auto (the best adapter of any); "
             "also $WGPURENDER_BACKEND",
    )


def add_anisotropy_arg(parser: argparse.ArgumentParser) -> None:
    """--anisotropy, with the same choices and default on every command that draws a scene."""
    from wgpurender.core.plan.anisotropy import ANISOTROPY_HELP, ANISOTROPY_RULES, DEFAULT_ANISOTROPY

    parser.add_argument("--anisotropy", choices=ANISOTROPY_RULES, default=DEFAULT_ANISOTROPY, help=ANISOTROPY_HELP)


camera_arg = checked(lambda text: checks.integer(text, "--camera", 0, 2**31 - 1))


def add_camera_arg(parser: argparse.ArgumentParser) -> None:
    """--camera K: a scene viewed through camera K of its glTF model (core/scene/gltf_cameras.py)."""
    parser.add_argument("--camera", type=camera_arg, default=None, metavar="K",
                        help="a scene: view through camera K of its glTF model's cameras (--explain lists them) "
                        "instead of its [camera]")


def add_render_args(parser: argparse.ArgumentParser) -> None:
    """--size, --msaa, --format, --time: how a stage or scene is rendered."""
    parser.add_argument("--size", type=size_arg, default=None, metavar="WxH",
                        help="image size (default: a stage 800x600, a scene its own [render] size)")
    parser.add_argument(
        "--msaa", type=msaa_arg, default=None, metavar="N", help="MSAA sample count, 1 or 4 (default: the stage's)"
    )
    parser.add_argument(
        "--format",
        type=format_arg,
        default=None,
        metavar="F",
        help="colour format: rgba8unorm, rgba8unorm-srgb (default) or rgba16float",
    )
    parser.add_argument(
        "--time",
        type=time_arg,
        default=0.0,
        metavar="T",
        help="a stage's animation time in seconds, fixed so output is deterministic (default 0); for a scene, the "
        "time its glTF models' animations are posed at (a static scene: only 0)",
    )
    add_backend_arg(parser)
