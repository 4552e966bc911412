"""The implementation matrix (``wgpurender verify --implementations raw,wgpu-vulkan,wgpu-gl,browser``): every stage
and repository scene rendered on each implementation at one size, and every pair compared.

Metrics per pair: max (largest channel difference, 1/255), the share of pixels off by more than 1/255, PSNR and
mean FLIP (core/verdict/compare.py). Bounds: each implementation against the reference one, ``wgpu-vulkan``, with the
calibrated rows of assets/reference/implementations.toml at the image's size class, and the size-free radial and
detail bounds that catch a dropped post effect (core/verdict/structure.py) (``raw`` against ``wgpu-vulkan``: exact
on one device, except the post-chain bound that verify.py explains). Pairs of two non-reference implementations are
reported without a bound (``info``): their distance is at most the sum of their two bounded distances.

Writes ``implementations.md``, ``implementations.csv`` and ``heatmaps/impl-*.png``. ``calibrate=True`` rewrites
the measured implementations' rows of implementations.toml from this run (bounds per the CPU-driver rule).
"""

from __future__ import annotations

import csv
import datetime
import io
import itertools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import save_png
from wgpurender.core.verdict.compare import Comparison, compare_images, heatmap
from wgpurender.core.verdict.structure import structure
from wgpurender.core.verdict.tolerances import Tolerance, Uncalibrated, driver_class, implementation_tolerance, measure

REFERENCE = "wgpu-vulkan"
FIELDS = ("target", "a", "b", "status", "max_abs", "over_1", "psnr", "flip_mean", "bound", "note", "heatmap")


@dataclass
class Cell:
    target: str
    a: str
    b: str
    status: str  # identical | pass | FAIL | info | skipped
    comparison: Comparison | None = None
    bound: str = ""
    note: str = ""
    heatmap: str = ""

    def row(self) -> dict:
        c = self.comparison
        return {"target": self.target, "a": self.a, "b": self.b, "status": self.status,
                "max_abs": "" if c is None else c.max_abs, "over_1": "" if c is None else f"{c.over_1:.6f}",
                "psnr": "" if c is None else f"{c.psnr:.2f}", "flip_mean": "" if c is None else f"{c.flip_mean:.6f}",
                "bound": self.bound, "note": self.note, "heatmap": self.heatmap}


@dataclass
class MatrixReport:
    implementations: list[str]
    missing: dict[str, str]
    who: dict[str, str]  # implementation -> device / browser it ran on
    size: tuple[int, int]
    date: str
    cells: list[Cell]
    differs: str = ""  # what the matrix draws unlike `wgpurender render T` on this adapter, and why

    @property
    def failed(self) -> list[Cell]:
        return [c for c in self.cells if c.status == "FAIL"]


def _bound(a: str, b: str, target: str) -> Tolerance | None:
    if REFERENCE not in (a, b):
        return None
    other = b if a == REFERENCE else a
    if other == "raw":
        from wgpurender.core.scene import load_scene
        from wgpurender.implementations import scene_files
        from wgpurender.verify import CHAIN_BOUND, EXACT

        scene = scene_files().get(target)
        return CHAIN_BOUND if scene is not None and len(load_scene(scene).post) >= 2 else EXACT
    from wgpurender.wgpu_path.device.context import get_context

    return implementation_tolerance(other, target, cls=driver_class(get_context("Vulkan").adapter.info["device"]))


def _compare(out: Path, target: str, a: str, b: str, ia: np.ndarray, ib: np.ndarray) -> Cell:
    comparison = compare_images(ia, ib)
    try:
        tol = _bound(a, b, target)
        tol = None if tol is None else tol.at_size(ia.shape[1], ia.shape[0])
    except (Uncalibrated, UserError) as err:  # a bound that does not apply here fails loudly, never "info"
        return Cell(target, a, b, "FAIL", comparison, "uncalibrated", f"uncalibrated: {err}")
    note = ""
    if np.array_equal(ia, ib):
        return Cell(target, a, b, "identical", comparison, _text(tol), note)
    cell = Cell(target, a, b, "info" if tol is None else "pass", comparison, _text(tol), note)
    if tol is not None:
        exceeded = (tol.exceeded(measure(ia, ib)) + tol.structure_exceeded(structure(ia, ib))
                    if tol.name != "exact" else ["not identical"])
        if exceeded:
            cell.status, cell.note = "FAIL", "; ".join(exceeded)
    path = out / "heatmaps" / f"impl-{target}-{a}-{b}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    save_png(path, heatmap(ia, ib))
    cell.heatmap = str(path.relative_to(out))
    return cell


def _text(tol: Tolerance | None) -> str:
    if tol is None:
        return "none (info)"
    if tol.name == "exact":
        return "exact"
    size_free = "" if tol.radial is None else f", radial {tol.radial:g}/255, detail {tol.detail:g}"
    at = f" ({tol.size} class)" if tol.size else ""
    return f"max {tol.max_abs}/255{at}, changed {100 * tol.changed:.1f}%, FLIP {tol.flip_mean:.4f}{size_free}"


def render_all(implementations: list[str], targets: list[str], size: tuple[int, int], work: Path):
    """(images[impl][target], skipped[impl][target] = reason, who[impl])."""
    from wgpurender import implementations as impls
    from wgpurender.wgpu_path.device.context import get_context

    images, skipped, who = {}, {}, {}
    for impl in implementations:
        images[impl], skipped[impl] = {}, {}
        if impl == "browser":
            images[impl], skipped[impl], who[impl] = impls.render_browser(targets, size, work / "pages")
            continue
        if impl in ("wgpu-gl", "wgpu-dawn"):
            images[impl] = impls.render_in_child(impl, targets, size, work / impl)
            skipped[impl] = impls.child_skipped(work / impl)
            native = "Dawn through wgpudawn" if impl == "wgpu-dawn" else "wgpu-native"
            who[impl] = (work / impl / "adapter.txt").read_text() + f" ({native}, child process)"
            continue
        for name in targets:
            try:
                images[impl][name] = (impls.render_raw(name, size) if impl == "raw" else
                                      impls.render_wgpu(name, size, "Vulkan"))
            except UserError as err:
                skipped[impl][name] = str(err)
        who[impl] = get_context("Vulkan").describe() + (" (raw Vulkan path)" if impl == "raw" else "")
    return images, skipped, who


def run_matrix(out: Path, implementations: list[str], missing: dict[str, str], targets: list[str],
               size: tuple[int, int], calibrate: bool = False) -> MatrixReport:
    (out / "heatmaps").mkdir(parents=True, exist_ok=True)
    images, skipped, who = render_all(implementations, targets, size, out / "work")
    cells = []
    for target in targets:
        for a, b in itertools.combinations(implementations, 2):
            gone = [f"{i}: {skipped[i][target]}" for i in (a, b) if target in skipped[i]]
            if gone:
                cells.append(Cell(target, a, b, "skipped", note="; ".join(gone)))
            else:
                cells.append(_compare(out, target, a, b, images[a][target], images[b][target]))
    if calibrate:
        _calibrate(images, implementations, who, size)
        cells = [_compare(out, c.target, c.a, c.b, images[c.a][c.target], images[c.b][c.target])
                 if c.status != "skipped" else c for c in cells]
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    report = MatrixReport(implementations, missing, who, size, now, cells, _differs())
    (out / "implementations.md").write_text(markdown(report))
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=FIELDS)
    writer.writeheader()
    writer.writerows(c.row() for c in cells)
    (out / "implementations.csv").write_text(buf.getvalue())
    return report


def _differs() -> str:
    from wgpurender.core.plan.anisotropy import reference_difference
    from wgpurender.wgpu_path.device.context import get_context

    return reference_difference(get_context("Vulkan").adapter.info.get("adapter_type"))


def _calibrate(images: dict, implementations: list[str], who: dict, size: tuple[int, int]) -> None:
    from wgpurender.implementations import calibrate
    from wgpurender.verify import cpu_name

    if REFERENCE not in implementations:
        raise UserError("--calibrate needs wgpu-vulkan among the implementations (the reference)")
    for impl in implementations:
        if impl in (REFERENCE, "raw"):
            continue
        measured = {t: (measure(images[REFERENCE][t], img), structure(images[REFERENCE][t], img))
                    for t, img in images[impl].items() if t in images[REFERENCE]}
        bounded_by = (f"{who[impl]} vs {who[REFERENCE]}, CPU {cpu_name()}, {size[0]}x{size[1]}, "
                      f"{datetime.date.today()} (wgpurender verify --calibrate)")
        calibrate(impl, {f"{size[0]}x{size[1]}": measured}, bounded_by, driver_class(who[REFERENCE]))


def markdown(report: MatrixReport) -> str:
    lines = [f"Implementations at {report.size[0]}x{report.size[1]}, {report.date}:", ""]
    lines += [f"- `{impl}`: {report.who.get(impl, '')}" for impl in report.implementations]
    lines += [f"- `{impl}`: not available ({why})" for impl, why in report.missing.items()]
    lines += [f"- unlike `render T`: {report.differs}"] if report.differs else []
    lines += ["", "| target | pair | status | max | >1/255 | PSNR dB | FLIP | bound |",
              "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for c in report.cells:
        m = c.comparison
        nums = ("", "", "", "") if m is None else (
            str(m.max_abs), f"{100 * m.over_1:.2f}%", "inf" if m.psnr == float("inf") else f"{m.psnr:.1f}",
            f"{m.flip_mean:.4f}")
        status = c.status + (f": {c.note}" if c.note else "")
        lines.append(f"| {c.target} | {c.a} / {c.b} | {status} | {' | '.join(nums)} | {c.bound} |")
    return "\n".join(lines) + "\n"
