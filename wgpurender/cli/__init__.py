"""The ``wgpurender`` command line. Each subcommand is a module in this package (wgpurender/cli/).

A module there defines ``register(subparsers)``, which adds its parser and sets
``func`` to a function taking the parsed arguments and returning an exit code.
Every error the user can fix ends as one line on stderr and exit code 2.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import pkgutil
import sys
import warnings

import numpy as np

from wgpurender import __version__
from wgpurender.core.errors import UserError
from wgpurender.core.files.safe_write import install_signal_handlers
from wgpurender.wgpu_path.device import shader_errors


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line (the usage text is in --help)."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(
        prog="wgpurender",
        description="The steps of a Vulkan course on wgpu, headless or in a window, checked against a raw-Vulkan "
        "reference path.",
    )
    parser.add_argument("--version", action="version", version=f"wgpurender {__version__}")
    subparsers = parser.add_subparsers(dest="command", required=True, parser_class=OneLineParser)
    for mod in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if mod.name.startswith("_"):
            continue
        importlib.import_module(f"{__name__}.{mod.name}").register(subparsers)
    return parser


def _innermost(parser: argparse.ArgumentParser, args: argparse.Namespace) -> argparse.ArgumentParser:
    """The (sub)command parser ``args`` ran: ``wgpurender bench perf``'s for ``bench perf ...``."""
    while True:
        subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
        chosen = getattr(args, subs[0].dest, None) if subs else None
        if chosen not in (subs[0].choices if subs else {}):
            return parser
        parser = subs[0].choices[chosen]


def one_line(text: str) -> str:
    """A message on one line: line breaks and other control characters written as escapes (\\n, \\x00)."""
    return "".join(ch if ch.isprintable() else repr(ch)[1:-1] for ch in str(text))


def _quiet_libraries() -> None:
    """Library warnings and log records never reach stderr as extra lines: the error message says what went wrong.

    Python's last-resort logging handler prints WARNING records of loggers with no handler (trimesh's, ours);
    a NullHandler on the package loggers stops that. Python warnings are ignored for the run. wgpu's logger is
    left alone: wgpu installs its own logger class when imported (getting it first breaks that import), and its
    records include GPU validation errors, which are bugs to be seen.
    """
    for name in ("trimesh", "wgpurender", "PIL"):
        logger = logging.getLogger(name)
        if not any(isinstance(h, logging.NullHandler) for h in logger.handlers):
            logger.addHandler(logging.NullHandler())
    warnings.simplefilter("ignore")


def main(argv: list[str] | None = None) -> int:
    """Run one command. A user error is exactly one line on stderr and exit code 2; SIGTERM and Ctrl-C end the
    run through exceptions, so output files are complete or absent and no temp file stays behind."""
    try:
        parser = build_parser()
        args, extra = parser.parse_known_args(argv)
        if extra:  # refused by the command they were given to, pointing at its --help (not the top level's)
            _innermost(parser, args).error(f"unrecognized arguments: {' '.join(extra)}")
    except SystemExit as exit_:  # --help, or a usage error already printed as one line
        return int(exit_.code or 0)
    install_signal_handlers()
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            _quiet_libraries()
            return int(args.func(args) or 0)
    except UserError as err:
        print(f"wgpurender {args.command}: error: {one_line(err)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # e.g. piped into head: the reader has all it wanted
        sys.stderr.close()
        return 0
    except Exception as err:  # a pipeline error from user-supplied shaders is a user error; anything else a bug
        user = shader_errors.as_user_error(err)
        if user is None:
            raise
        print(f"wgpurender {args.command}: error: {one_line(user)}", file=sys.stderr)
        return 2
