"""Argument checks shared by the command line and the Python API: one message for one mistake.

Each function takes a value as the user gave it (a CLI string or a Python object), returns it in the type the
renderer needs, or raises :class:`UserError` saying what was wrong and what is valid. The CLI's argparse types
(``cli/_args.py``) call these with the text of the argument; ``wgpurender.api`` calls them with Python values;
so ``--gain 0`` and ``heatmap(gain=0)`` fail with the same words.

Python's ``bool`` is an ``int``: it is refused wherever a number is expected (``msaa=True`` is a mistake, not 1).
A string where a number is expected is refused too (``gain="32"``), except command-line text, which the CLI
marks as :class:`CliText` before calling a check.
"""

from __future__ import annotations

import math
import numbers
from typing import TYPE_CHECKING, Any

from wgpurender.core.course.formats import OUTPUT_FORMATS, SAMPLE_COUNTS
from wgpurender.core.errors import UserError

if TYPE_CHECKING:  # numpy is imported where a check needs it: the backend check runs before the device is
    import numpy as np  # started on a thread (wgpu_path/device/context.start_context), numpy while it is made

MAX_SIZE = 16384  # per side: the largest 2D texture any adapter we support offers
MAX_GAP = 4096
BACKENDS = ("Vulkan", "OpenGL", "Metal", "D3D12", "auto")  # as the adapter names them; auto: the best of any
BACKEND_ALIASES = {"gl": "OpenGL", "gles": "OpenGL", "dx12": "D3D12"}  # wgpu-native's instance names, and GLES


class CliText(str):
    """Text from the command line: a number check parses it (a plain ``str`` from Python code is refused)."""


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _is_bool(value: Any) -> bool:
    """Python's or numpy's bool (without importing numpy, as :func:`_is_array`)."""
    import sys

    numpy = sys.modules.get("numpy")
    return isinstance(value, bool) or (numpy is not None and isinstance(value, numpy.bool_))


def _is_array(value: Any) -> bool:
    """A numpy array (without importing numpy: no array exists until something did)."""
    import sys

    numpy = sys.modules.get("numpy")
    return numpy is not None and isinstance(value, numpy.ndarray)


def _is_number(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not _is_bool(value)


def _is_integer(value: Any) -> bool:
    return isinstance(value, numbers.Integral) and not _is_bool(value)


def number(value: Any, name: str) -> float:
    """A finite real number; a numeric string (the CLI's) is parsed. NaN and infinities are refused: a NaN
    threshold or time would switch a check off or draw one colour, silently."""
    if isinstance(value, CliText):
        try:
            value = float(value)
        except ValueError:
            raise UserError(f"{name} must be a number, got {_shown(str(value))}") from None
    elif not _is_number(value):
        raise UserError(f"{name} must be a number, got {type(value).__name__} {_shown(value)}")
    value = float(value)
    if not math.isfinite(value):
        raise UserError(f"{name} must be a finite number, got {value!r}: give a plain number such as 1.5")
    return value


def positive(value: Any, name: str, example: str = "32") -> float:
    """A finite number above 0."""
    value = number(value, name)
    if value <= 0:
        raise UserError(f"{name} must be above 0, got {value:g}: e.g. {example}")
    return value


def integer(value: Any, name: str, low: int, high: int) -> int:
    """A whole number in [low, high]; a digit string (the CLI's) is parsed; 4.0 and True are refused."""
    if isinstance(value, CliText):
        try:
            value = int(value.strip())
        except ValueError:
            raise UserError(f"{name} must be a whole number, got {_shown(str(value))}") from None
    elif not _is_integer(value):
        raise UserError(f"{name} must be a whole number ({low}..{high}), got {type(value).__name__} {_shown(value)}")
    value = int(value)
    if not low <= value <= high:
        raise UserError(f"{name} must be {low}..{high}, got {value}")
    return value


def size(value: Any, name: str = "size") -> tuple[int, int] | None:
    """(width, height) from ``"WxH"`` or a pair of whole numbers, each 1..16384; None stays None (the default)."""
    if value is None:
        return None
    if isinstance(value, str):
        parts = value.lower().split("x")
        if len(parts) != 2 or not all(p.strip().isdecimal() for p in parts):  # what int() takes ('²' isdigit)
            raise UserError(f"malformed {name} {value!r}: expected WIDTHxHEIGHT, e.g. 800x600")
        value = (int(parts[0]), int(parts[1]))
    if _is_array(value):
        value = value.tolist()
    if not isinstance(value, (tuple, list)) or len(value) != 2 or not all(_is_integer(v) for v in value):
        raise UserError(f"malformed {name} {_shown(value)}: expected (width, height) as two whole numbers "
                        "or 'WIDTHxHEIGHT', e.g. (800, 600)")
    width, height = int(value[0]), int(value[1])
    if not (0 < width <= MAX_SIZE and 0 < height <= MAX_SIZE):
        raise UserError(f"{name} {width}x{height} out of range: width and height must be 1..{MAX_SIZE}")
    return width, height


SAMPLE_COUNT_SHAPES = (1, 2, 4, 8, 16)  # what any API calls a sample count; the adapter says which it offers


def msaa(value: Any) -> int | None:
    """A sample count (1, 2, 4, 8, 16: which of them the adapter offers is checked where the adapter is known;
    WebGPU guarantees :data:`SAMPLE_COUNTS`), or None (the stage's or scene's own)."""
    if value is None:
        return None
    count = integer(value, "msaa", 1, 64)
    if count not in SAMPLE_COUNT_SHAPES:
        raise UserError(f"msaa must be a sample count such as {', '.join(map(str, SAMPLE_COUNTS))}, got {count}")
    return count


def output_format(value: Any) -> str | None:
    """A colour format both paths render into and write to a PNG (core/course/formats.py), or None."""
    if value is None:
        return None
    if not isinstance(value, str) or value not in OUTPUT_FORMATS:
        raise UserError(f"unsupported colour format {_shown(value)}: choose one of {', '.join(OUTPUT_FORMATS)}")
    return value


def backend(value: Any) -> str | None:
    """A wgpu backend name (any case) in its canonical spelling, or None (the default or $WGPURENDER_BACKEND)."""
    if value is None:
        return None
    if isinstance(value, str):
        name = BACKEND_ALIASES.get(value.lower(), value)
        for known in BACKENDS:
            if name.lower() == known.lower():
                return known
    raise UserError(f"unknown backend {_shown(value)}: choose one of {', '.join(b.lower() for b in BACKENDS[:-1])} "
                    "or auto (--backend or $WGPURENDER_BACKEND)")


def time(value: Any) -> float:
    """An animation time in seconds: finite (t = inf made every rotation NaN: a one-colour image)."""
    return number(value, "t (the animation time)")


def gain(value: Any) -> float:
    """The heatmap's magnification: finite and above 0 (0 divided by zero; NaN or -1 drew every difference
    black, i.e. 'equal')."""
    return positive(value, "gain", "32")


def gap(value: Any) -> int:
    """Pixels between images side by side."""
    return integer(value, "gap", 0, MAX_GAP)


def threshold(name: Any, value: Any) -> tuple[str, float]:
    """A compare threshold: a known metric and a finite value (a NaN threshold never fails: black vs white
    passed). Shares and differences are >= 0; a share may be given as a percentage string ('0.5%')."""
    from wgpurender.core.verdict.compare import METRICS

    if name not in METRICS:
        raise UserError(f"unknown metric {_shown(name)}: choose from {', '.join(METRICS)}")
    scale = 1.0
    if isinstance(value, CliText) and value.strip().endswith("%"):
        value, scale = CliText(value.strip()[:-1]), 0.01
    limit = number(value, f"threshold {name}") * scale
    if name != "psnr" and limit < 0:
        raise UserError(f"threshold {name} must be 0 or more, got {limit:g}")
    top = _THRESHOLD_TOPS.get(name)
    if top is not None and limit > top[0]:  # a limit above the metric's range never fails: no check at all
        raise UserError(f"threshold {name} must be at most {top[1]}, got {limit:g}: it could never fail"
                        f"{' (a percentage needs a %: 0.5%)' if name.startswith('over_') else ''}")
    return name, limit


# The metrics' ranges, from their definitions: shares of pixels and FLIP's per-pixel error are in [0, 1],
# a difference of 8-bit values is at most 255.
_THRESHOLD_TOPS = {"over_1": (1.0, "1 (100%)"), "over_2": (1.0, "1 (100%)"), "flip_mean": (1.0, "1"),
                   "max_abs": (255.0, "255")}


def choice(value: Any, name: str, choices: tuple[str, ...]) -> str:
    """One of a few named settings."""
    if not isinstance(value, str) or value not in choices:
        raise UserError(f"{name} must be one of {', '.join(choices)}, got {_shown(value)}")
    return value


def image_array(array: Any, name: str) -> np.ndarray:
    """8-bit sRGB-encoded (H, W, 3|4) pixels from a numpy image.

    uint8: as stored. uint16: scaled by 1/257 (65535 -> 255; read as 8-bit, 1/65535 counted as 255). float:
    linear light, sRGB-encoded (NaN refused: an all-NaN image compared 'identical' to zeros). Other dtypes,
    other shapes and empty images are refused.
    """
    import numpy as np

    from wgpurender.core.files.imageio import to_uint8

    if not isinstance(array, np.ndarray):
        raise UserError(f"{name}: expected a numpy array, got {type(array).__name__}")
    if array.ndim != 3 or array.shape[2] not in (3, 4):
        raise UserError(f"{name}: expected an (height, width, 3 or 4) image array, got shape {array.shape}")
    if array.shape[0] == 0 or array.shape[1] == 0:
        raise UserError(f"{name}: the image is empty ({array.shape[1]}x{array.shape[0]} pixels)")
    if array.dtype == np.uint8:
        return np.ascontiguousarray(array)
    if array.dtype == np.uint16:
        return np.round(array.astype(np.float64) / 257.0).astype(np.uint8)
    if array.dtype.kind == "f":
        if not np.isfinite(array).all():
            raise UserError(f"{name}: the image has NaN or infinite pixels; float images must be finite linear "
                            "values")
        return to_uint8(np.ascontiguousarray(array))
    raise UserError(f"{name}: pixels of dtype {array.dtype} are not supported: give uint8, uint16 or float "
                    "(linear) pixels")


def output_path(value: Any, name: str) -> str:
    """A file or folder path to write: a non-empty ``str`` or ``os.PathLike`` without NUL characters."""
    import os

    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    if not isinstance(value, str) or not value:
        raise UserError(f"{name} must be a folder or file path (str or pathlib.Path), got {_shown(value)}")
    if "\0" in value:
        raise UserError(f"{name} {_shown(value)}: the path contains a NUL character")
    return value


def flag(value: Any, name: str) -> bool:
    """True or False (numpy's bool too); anything else, 1 and "yes" among them, is refused."""
    if not _is_bool(value):
        raise UserError(f"{name} must be True or False, got {type(value).__name__} {_shown(value)}")
    return bool(value)
