"""How far a fresh render may be from a committed reference image: the calibrated tolerance table.

Exact equality holds only between two renders made in the same run on the same machine:
llvmpipe's generated code differs between host CPUs, and a GPU rasterises and filters within
the Vulkan spec's tolerances but not like lavapipe. Committed references
(``assets/reference/*.png``, made by the raw-Vulkan path only, and the C++ tutorial's frames)
are therefore compared with per-reference, per-driver-class tolerances read from ONE table,
``assets/reference/tolerances.toml``, that also records what each bound was calibrated from.

Three metrics, all of the RGBA channels in 1/255 units except FLIP (RGB):
``max_abs`` (largest channel difference), ``changed`` (share of pixels with any channel
different) and ``flip_mean`` (mean LDR FLIP). A check fails when any one exceeds its bound.

API-free: imports no GPU API and neither render path.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.assets import reference_dir
from wgpurender.core.verdict.structure import Structure

TABLE_PATH = reference_dir() / "tolerances.toml"
DRIVER_CLASSES = ("lavapipe", "gpu")


@dataclass(frozen=True)
class Metrics:
    """How far ``actual`` is from ``expected``."""

    max_abs: int  # largest difference of any channel, in 1/255
    changed: float  # share of pixels with any channel different
    changed_pixels: int
    flip_mean: float  # mean LDR FLIP error of the RGB channels, 0 .. 1
    pixels: int

    def as_dict(self) -> dict:
        return asdict(self)

    def summary(self) -> str:
        return (f"max diff {self.max_abs}/255, {self.changed_pixels} of {self.pixels} pixels changed "
                f"({100 * self.changed:.3f}%), FLIP mean {self.flip_mean:.5f}")


@dataclass(frozen=True)
class Tolerance:
    """The bounds for one reference on one driver class, and where they come from."""

    name: str
    driver_class: str
    max_abs: int
    changed: float
    flip_mean: float
    measured: str  # the spread the bounds were calibrated from
    bounded_by: str  # the drivers/CPUs/GPUs that measured it
    provisional: bool
    radial: float | None = None  # size-free bounds of structure.py (None: not bounded)
    detail: float | None = None
    size: str = ""  # "WxH" the three metrics were calibrated at ("": any size)
    sizes: tuple = ()  # (("WxH", {bound: value}), ...): the metrics' size classes above ``size``

    def at_size(self, width: int, height: int) -> Tolerance:
        """These bounds for an image of ``width`` x ``height``: the smallest calibrated size class with at least
        as many pixels (max grows with the pixel count; the changed share and FLIP are means, kept unless the
        class measured its own). Above the largest class, :class:`Uncalibrated`."""
        if not self.size:
            return self
        classes = sorted(((size_pixels(self.size), self.size, {}), *((size_pixels(k), k, v) for k, v in self.sizes)))
        for pixels, name, bounds in classes:
            if width * height <= pixels:
                fields = {k: bounds[k] for k in ("max_abs", "changed", "flip_mean") if k in bounds}
                return dataclasses.replace(self, size=name, sizes=(), **fields)
        raise Uncalibrated(f"the {self.driver_class} bounds for {self.name} were calibrated up to {classes[-1][1]}, "
                           f"not {width}x{height}: run `wgpurender verify --implementations ... --calibrate --size "
                           f"{width}x{height}` on this machine")

    def structure_exceeded(self, measured: Structure) -> list[str]:
        """One line per size-free bound (structure.py) that ``measured`` exceeds, naming what it catches."""
        out = []
        if self.radial is not None and measured.radial > self.radial:
            out.append(f"radial shift {measured.radial:g}/255 > {self.radial:g}/255 (a ring moved one way: "
                       "tone, colour or vignette)")
        if self.detail is not None and abs(measured.detail) > self.detail:
            out.append(f"detail change {measured.detail:+.3f} beyond +-{self.detail:g} (log2 gradient: sharpen or "
                       "anti-aliasing)")
        return out

    def exceeded(self, metrics: Metrics) -> list[str]:
        """One line per bound that ``metrics`` exceeds (empty: within tolerance)."""
        out = []
        if metrics.max_abs > self.max_abs:
            out.append(f"max diff {metrics.max_abs}/255 > {self.max_abs}/255")
        if metrics.changed > self.changed:
            out.append(f"changed pixels {100 * metrics.changed:.3f}% > {100 * self.changed:.3f}%")
        if metrics.flip_mean > self.flip_mean:
            out.append(f"FLIP mean {metrics.flip_mean:.5f} > {self.flip_mean:.5f}")
        return out

    def describe(self) -> str:
        state = "PROVISIONAL " if self.provisional else ""
        return (f"{state}{self.driver_class} tolerance for {self.name}: max diff {self.max_abs}/255, changed "
                f"{100 * self.changed:.3f}%, FLIP {self.flip_mean:.5f} (bounded by {self.bounded_by}; "
                f"measured {self.measured})")


def size_pixels(size: str) -> int:
    """The pixel count of a "WxH" size."""
    width, height = (int(v) for v in size.split("x"))
    return width * height


def driver_class(device_name: str) -> str:
    """'lavapipe' for Mesa's CPU driver (any x86-64 CPU), 'gpu' for everything else (calibrated on NVIDIA)."""
    return "lavapipe" if "llvmpipe" in device_name.lower() else "gpu"


def _as_rgba8(image: np.ndarray, what: str) -> np.ndarray:
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] not in (3, 4) or image.dtype != np.uint8:
        raise UserError(f"{what}: expected an 8-bit RGB or RGBA image, got {image.dtype} {image.shape}")
    return image


def measure(expected: np.ndarray, actual: np.ndarray) -> Metrics:
    """The three metrics of ``actual`` against ``expected`` (both 8-bit, same size and channels)."""
    from wgpurender.core.verdict.compare import flip_mean

    a, b = _as_rgba8(expected, "expected"), _as_rgba8(actual, "actual")
    if a.shape != b.shape:
        raise UserError(f"images differ in shape: expected {a.shape}, actual {b.shape}")
    diff = np.abs(a.astype(np.int16) - b.astype(np.int16)).max(axis=-1)
    changed = int(np.count_nonzero(diff))
    flip = flip_mean(a[..., :3], b[..., :3])[0] if changed else 0.0
    return Metrics(int(diff.max()), changed / diff.size, changed, float(flip), int(diff.size))


def load_table(path: Path = TABLE_PATH) -> dict:
    try:
        return tomllib.loads(path.read_text())
    except FileNotFoundError:
        raise UserError(f"tolerance table {path} not found") from None
    except tomllib.TOMLDecodeError as err:
        raise UserError(f"tolerance table {path}: {err}") from None


def tolerance(name: str, cls: str, table: dict | None = None) -> Tolerance:
    """The bounds for reference ``name`` on driver class ``cls``, from the table."""
    table = load_table() if table is None else table
    row = table.get("references", {}).get(name, {}).get(cls)
    if row is None:
        raise UserError(f"no {cls} tolerance for reference '{name}' in {TABLE_PATH.name}: measure it with "
                        "`wgpurender verify` and add the row")
    info = table.get("classes", {}).get(cls, {})
    return Tolerance(name, cls, int(row["max_abs"]), float(row["changed"]), float(row["flip_mean"]),
                     str(row.get("measured", "")), str(info.get("bounded_by", "")),
                     bool(row.get("provisional", info.get("provisional", False))))


def _round_up(value: float, digits: int = 2) -> float:
    """Round up to ``digits`` significant figures (bounds read better, and never shrink)."""
    if value <= 0:
        return 0.0
    scale = 10 ** (digits - 1 - math.floor(math.log10(value)))
    return math.ceil(round(value * scale, 9)) / scale  # 2 x 0.07 is 0.14000000000000001: not 0.15


def calibrate(spread: list[Metrics], cls: str) -> dict:
    """Bounds from measured spread: the rule the table's rows follow (see its header).

    max_abs: the largest measured + 1, at least 2 (lavapipe; 3/255 always fails), or x1.5 + 1 (a GPU);
    changed and FLIP: twice the largest measured, with floors (1% of pixels, FLIP 0.002) so that a
    reference that happened to be identical on the machines measured still has room for another
    CPU's rounding.
    """
    worst_max = max(m.max_abs for m in spread)
    max_abs = max(2, worst_max + 1) if cls == "lavapipe" else min(255, math.ceil(1.5 * worst_max) + 1)
    changed = max(0.01, _round_up(2 * max(m.changed for m in spread)))
    flip = max(0.002, _round_up(2 * max(m.flip_mean for m in spread)))
    return {"max_abs": max_abs, "changed": min(1.0, changed), "flip_mean": flip}


def calibrate_structure(spread: list[Structure], sizes: list[str]) -> dict:
    """The size-free bounds (structure.py) from their spread over ``sizes``: radial = worst + 1/255 (a ring's
    median is 0 between implementations that differ sign-balanced); detail = 2 x the worst magnitude, at least
    0.02 (the log2 edge-gradient ratio: a dropped FXAA measured 0.29-0.45, a dropped sharpen -0.41 to -0.52, at
    160x120 to 640x480 in docs/runs/2026-11-27-size-free-bounds)."""
    radial = max(s.radial for s in spread)
    detail = max(abs(s.detail) for s in spread)
    return {"radial": radial + 1, "detail": max(0.02, _round_up(2 * detail)),
            "structure_measured": f"radial {radial:g}/255, detail {detail:.4f} (worst of {', '.join(sizes)})"}


HEADER = """\
# Tolerances for comparing fresh renders with committed reference images (read by tests/imagecheck.py
# and `wgpurender verify`; written by hand or by `wgpurender verify --out DIR`, which writes DIR/tolerances.toml
# with the current driver class's rows re-calibrated from what it measured).
#
# [classes.X]: a driver class. 'lavapipe' = Mesa's CPU driver on any x86-64 CPU; 'gpu' = any other adapter,
# calibrated on NVIDIA. bounded_by names the drivers/CPUs/GPUs whose spread the bounds come from.
# [references.NAME.CLASS]: max_abs (largest channel difference, 1/255), changed (share of pixels with any
# channel different), flip_mean (mean LDR FLIP, RGB). A comparison fails when any one is exceeded.
# measured: the spread the row was calibrated from. Calibration rule (wgpurender/core/verdict/tolerances.calibrate):
# max_abs = worst + 1, at least 2 (lavapipe) or 1.5 x worst + 1 (gpu); changed, flip_mean = 2 x worst,
# at least 1% and 0.002. Rows marked provisional are guesses from issue 12's notes, not yet measured.
# The tutorial rows also hold the issue's per-frame targets, checked by tests/test_vulkan_tutorial.py:
# mae (largest per-channel mean absolute error, 1/255) and within2 (least share of pixels within 2/255),
# with their provenance in targets. verify keeps them when it re-calibrates a row.
"""


def _value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items()) + " }"
    return repr(value)


def _key(key: str) -> str:
    return key if key.replace("_", "").replace("-", "").isalnum() and key.isascii() else _value(key)


def format_table(table: dict) -> str:
    """The table as TOML text, in the layout of the committed file (tomllib only reads)."""
    lines = [HEADER]
    for cls, info in table.get("classes", {}).items():
        lines.append(f"[classes.{cls}]")
        lines += [f"{key} = {_value(value)}" for key, value in info.items()]
        lines.append("")
    for name, rows in table.get("references", {}).items():
        for cls, row in rows.items():
            lines.append(f'[references."{name}".{cls}]')
            lines += [f"{key} = {_value(value)}" for key, value in row.items()]
            lines.append("")
    return "\n".join(lines)


# -- implementation pairs: the same target on two WebGPU stacks of one machine -------------------------------
IMPLEMENTATIONS_PATH = TABLE_PATH.with_name("implementations.toml")
IMPLEMENTATIONS_HEADER = """\
# Tolerances between implementations of the course on ONE machine: a target rendered by wgpu-native over
# Vulkan (the reference implementation) and by another stack at the same size (read by tests/test_backends.py,
# tests/test_export_browser.py and `wgpurender verify --implementations`).
#
# [implementations.IMPL]: bounded_by = the machine, drivers and date the spread was measured on; driver_class =
# the class (tolerances.driver_class) of the Vulkan adapter it was measured against: other classes are not bounded.
# [implementations.IMPL.targets.NAME]: max_abs (1/255), changed (share of pixels), flip_mean, measured (the
# spread). Rule (wgpurender/core/verdict/tolerances.calibrate, CPU drivers): max_abs = worst + 1, at least 2;
# changed, flip_mean = 2 x worst, at least 1% and 0.002. Written by wgpurender.implementations.calibrate.
# size = the image size the rows' three bounds hold for; a row's sizes = {"WxH" = {...}}: the same three for a
# larger size class (an image uses the smallest class with at least its pixel count; larger: uncalibrated).
# radial (1/255), detail (log2): the size-free bounds of core/verdict/structure.py, which catch a dropped post
# effect; rule (tolerances.calibrate_structure): radial = worst + 1, detail = 2 x worst, at least 0.02, with the
# spread over every size measured in structure_measured.
"""


class Uncalibrated(UserError):
    """The implementation's bounds were measured on another driver class than the one asked about."""


def implementation_tolerance(implementation: str, name: str, table: dict | None = None,
                             cls: str | None = None) -> Tolerance:
    """The bounds for target ``name`` on ``implementation`` against wgpu-native's Vulkan render of it; with
    ``cls`` (the Vulkan adapter's driver class), :class:`Uncalibrated` where the rows were measured on another."""
    if table is None:
        table = load_table(IMPLEMENTATIONS_PATH)
    impl = table.get("implementations", {}).get(implementation, {})
    measured_on = impl.get("driver_class", "lavapipe")
    if cls is not None and impl and cls != measured_on:
        raise Uncalibrated(f"the {implementation} bounds were calibrated on {measured_on}, not {cls}: run "
                           "`wgpurender verify --implementations ... --calibrate` on this machine")
    row = impl.get("targets", {}).get(name)
    if row is None:
        raise UserError(f"no {implementation} tolerance for '{name}' in {IMPLEMENTATIONS_PATH.name}: measure it "
                        "with `wgpurender verify --calibrate` and add the row")
    return Tolerance(name, implementation, int(row["max_abs"]), float(row["changed"]), float(row["flip_mean"]),
                     str(row.get("measured", "")), str(impl.get("bounded_by", "")), False,
                     _optional(row, "radial"), _optional(row, "detail"), str(impl.get("size", "")),
                     tuple(sorted(row.get("sizes", {}).items())))


def _optional(row: dict, key: str) -> float | None:
    return float(row[key]) if key in row else None


def format_implementation_table(table: dict) -> str:
    lines = [IMPLEMENTATIONS_HEADER]
    for impl, info in table.get("implementations", {}).items():
        lines.append(f'[implementations."{impl}"]')
        lines += [f"{key} = {_value(value)}" for key, value in info.items() if key != "targets"]
        lines.append("")
        for name, row in info.get("targets", {}).items():
            lines.append(f'[implementations."{impl}".targets."{name}"]')
            lines += [f"{key} = {_value(value)}" for key, value in row.items()]
            lines.append("")
    return "\n".join(lines)
