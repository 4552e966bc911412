"""The cross-driver equivalence matrix (``wgpurender verify``): both paths on this adapter, and this adapter
against the committed references, with the calibrated tolerances of assets/reference/tolerances.toml.

Rows, each a comparison of two 8-bit images (float outputs are sRGB-encoded first; exactness is
checked on the raw bytes):

- ``wgpu vs raw``: every stage both paths have, and every repository scene the raw path can draw,
  rendered here in this run. Exact, except scenes whose post chain has two or more effects: the wgpu
  path stores the colour between effects (float16, or 8-bit sRGB), the raw path keeps float32 in one
  shader (tests/test_vulkan_ref_scene.py explains and measures it), bounded by CHAIN_BOUND.
- ``raw vs committed``: the raw path's render against assets/reference/<name>.png, with this
  driver class's row of the table.
- ``wgpu vs C++ frame``: the Vulkan tutorial scenes against the C++ program's frames in
  ../shared/anchors (skipped, with the reason, when that folder is absent).

Writes ``verify.csv``, ``verify.md``, ``heatmaps/*.png`` (every comparison that is not identical)
and ``tolerances.toml``: the table with this driver class's rows re-calibrated from what was measured
here (bounds only grow for rows already measured elsewhere; provisional rows are replaced). On a new
device class, copying that file over assets/reference/tolerances.toml is the whole calibration.

Imports both render paths (like bench/); the CLI verb is wgpurender/cli/verify.py.
"""

from __future__ import annotations

import csv
import datetime
import io
import platform
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.assets import scene_dir
from wgpurender.core.files.imageio import load_png, save_png, to_uint8
from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY, reference_difference
from wgpurender.core.verdict.tolerances import (
    Metrics,
    Tolerance,
    calibrate,
    driver_class,
    format_table,
    load_table,
    measure,
    tolerance,
)

REPO = Path(__file__).resolve().parent.parent
SCENE_DIR = scene_dir()  # the checkout's assets/scenes, or the wheel's copy
ANCHORS = REPO.parent / "shared" / "anchors" / "vulkan-tutorial"
TUTORIAL_FRAMES = {"vulkan_tutorial_28": "ref_28_model_loading_1x.png",
                   "vulkan_tutorial_30": "ref_30_multisampling_4xMSAA.png"}
QUICK = {"stages": ("triangle", "3d"), "scenes": ("unlit",)}
# wgpu vs raw, scenes with a chain of 2+ post effects: float16 / 8-bit sRGB intermediates on the wgpu path only.
# Measured on lavapipe (tests/test_vulkan_ref_scene.py): max 1/255, FLIP <= 0.0061; the size-free bounds from
# docs/runs/2026-11-27-size-free-bounds (raw vs wgpu-vulkan, 160x120 to 640x480: radial 0/255, detail <= 0.0003).
CHAIN_BOUND = Tolerance("post chain", "same device", 1, 1.0, 0.01,
                        "lavapipe: max 1/255, FLIP 0.0018-0.0061 (tests/test_vulkan_ref_scene.py)",
                        "wgpu's stored intermediates vs the raw path's float32", False, radial=1.0, detail=0.02)
EXACT = Tolerance("exact", "same device", 0, 0.0, 0.0, "0 pixels differ (tests/test_vulkan_ref*.py)",
                  "same driver, same run", False)
CSV_FIELDS = ("device", "kind", "name", "comparison", "status", "max_abs", "changed_pixels", "changed", "flip_mean",
              "bound", "note", "heatmap")


@dataclass
class Row:
    kind: str  # stage | scene | tutorial
    name: str
    comparison: str  # wgpu vs raw | raw vs committed | wgpu vs C++ frame
    status: str  # identical | pass | FAIL | skipped
    metrics: Metrics | None = None
    bound: str = ""
    note: str = ""
    heatmap: str = ""
    reference: str = ""  # the table's row name, for calibration

    def as_csv(self, device: str) -> dict:
        m = self.metrics
        return {"device": device, "kind": self.kind, "name": self.name, "comparison": self.comparison,
                "status": self.status,
                "max_abs": "" if m is None else m.max_abs, "changed_pixels": "" if m is None else m.changed_pixels,
                "changed": "" if m is None else f"{m.changed:.6f}",
                "flip_mean": "" if m is None else f"{m.flip_mean:.6f}", "bound": self.bound, "note": self.note,
                "heatmap": self.heatmap}


@dataclass
class Report:
    device: str
    cpu: str
    driver_class: str
    date: str
    rows: list[Row] = field(default_factory=list)
    differs: str = ""  # what this run draws unlike `wgpurender render T` on this adapter, and why ('' when nothing)

    @property
    def failed(self) -> list[Row]:
        return [r for r in self.rows if r.status == "FAIL"]


def cpu_name() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _slug(*parts: str) -> str:
    return "-".join(p.replace(" ", "_").replace("/", "_").replace("+", "") for p in parts)


class Matrix:
    """Runs the comparisons and collects the rows; heatmaps go to ``out/heatmaps``."""

    def __init__(self, out: Path, cls: str, table: dict) -> None:
        self.out, self.cls, self.table = out, cls, table
        self.rows: list[Row] = []
        (out / "heatmaps").mkdir(parents=True, exist_ok=True)

    def compare(self, kind: str, name: str, comparison: str, expected: np.ndarray, actual: np.ndarray,
                tol: Tolerance, reference: str = "") -> Row:
        exp8, act8 = to_uint8(expected), to_uint8(actual)
        if expected.dtype == actual.dtype and expected.shape == actual.shape and np.array_equal(
                expected.view(np.uint8), actual.view(np.uint8)):
            row = Row(kind, name, comparison, "identical", measure(exp8, act8), _bound_text(tol), reference=reference)
        else:
            metrics = measure(exp8, act8)
            exceeded = tol.exceeded(metrics) if tol is not EXACT else ["not identical"]
            row = Row(kind, name, comparison, "FAIL" if exceeded else "pass", metrics, _bound_text(tol),
                      "; ".join(exceeded), reference=reference)
            row.heatmap = self._heatmap(row, exp8, act8)
        self.rows.append(row)
        return row

    def skip(self, kind: str, name: str, comparison: str, reason: str) -> None:
        self.rows.append(Row(kind, name, comparison, "skipped", note=reason))

    def _heatmap(self, row: Row, expected: np.ndarray, actual: np.ndarray) -> str:
        from wgpurender.core.verdict.compare import heatmap

        path = self.out / "heatmaps" / f"{_slug(row.kind, row.name, row.comparison)}.png"
        save_png(path, heatmap(expected, actual))
        if row.status == "FAIL":
            save_png(path.with_name(path.stem + "-actual.png"), actual)
        return str(path.relative_to(self.out))

    def committed(self, kind: str, name: str, ref_name: str, expected: np.ndarray, actual: np.ndarray,
                  comparison: str = "raw vs committed") -> None:
        try:
            tol = tolerance(ref_name, self.cls, self.table)
        except UserError as err:
            self.skip(kind, name, comparison, str(err))
            return
        self.compare(kind, name, comparison, expected, actual, tol, reference=ref_name)


def _bound_text(tol: Tolerance) -> str:
    if tol is EXACT:
        return "exact"
    flag = " (provisional)" if tol.provisional else ""
    return f"max {tol.max_abs}/255, changed {100 * tol.changed:.2f}%, FLIP {tol.flip_mean:.4f}{flag}"


def verify_stages(matrix: Matrix, names: list[str]) -> None:
    """Each stage on both paths at the references' size, then the raw render against its committed PNG."""
    from wgpurender.raw_path import render_reference
    from wgpurender.raw_path.make_references import REFERENCE_SIZE, reference_path
    from wgpurender.wgpu_path.render import render_stage
    from wgpurender.wgpu_path.stages import all_stages

    wgpu_stages = all_stages()
    for name in names:
        raw = render_reference(name, REFERENCE_SIZE)
        if name in wgpu_stages:
            ours = render_stage(name, REFERENCE_SIZE, None, None, 0.0, frames=1).pixels
            matrix.compare("stage", name, "wgpu vs raw", raw, ours, EXACT)
        else:
            matrix.skip("stage", name, "wgpu vs raw", "the wgpu path has no such stage")
        if reference_path(name).is_file():
            matrix.committed("stage", name, name, load_png(reference_path(name)), to_uint8(raw))
        else:
            matrix.skip("stage", name, "raw vs committed", f"{reference_path(name)} missing")


def _scene_size(scene_file: Path) -> tuple[int, int] | None:
    """Scenes at the scene references' size; the tutorial scenes at their own (the C++ frames' 800x600)."""
    from wgpurender.raw_path.make_references import SCENE_REFERENCE_SIZE

    return None if scene_file.stem in TUTORIAL_FRAMES else SCENE_REFERENCE_SIZE


def _needs_anchors(scene_file: Path) -> bool:
    return "shared/anchors" in scene_file.read_text() and not ANCHORS.is_dir()


def verify_scene(matrix: Matrix, scene_file: Path, committed: dict[str, str]) -> None:
    """One scene: wgpu vs raw (when the raw path can draw it), the committed reference, the C++ frame."""
    from wgpurender.core.scene import load_scene
    from wgpurender.raw_path.make_references import reference_path
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.wgpu_path.scene import render_scene_file

    name = scene_file.stem
    if _needs_anchors(scene_file):
        matrix.skip("scene", name, "wgpu vs raw", f"needs {ANCHORS} (the tutorial's model and texture), absent")
        return
    size = _scene_size(scene_file)
    # Both paths draw resolve_plan's plan for their adapter, with the scene's own anisotropy: the committed
    # references and the C++ tutorial frames were made with it, on every adapter (run_verify's note says so).
    ours = render_scene_file(scene_file, size=size, frames=1, anisotropy=REFERENCE_ANISOTROPY).pixels
    try:
        raw = render_scene_reference(scene_file, size=size, anisotropy=REFERENCE_ANISOTROPY)
    except UserError as err:
        why = str(err).split("cannot render this scene: ")[-1].split(";")[0]  # the first reason, no path
        matrix.skip("scene", name, "wgpu vs raw", f"the raw path cannot render it yet: {why}")
        raw = None
    if raw is not None:
        chain = len(load_scene(scene_file).post) >= 2
        matrix.compare("scene", name, "wgpu vs raw", raw, ours, CHAIN_BOUND if chain else EXACT)
    ref_name = committed.get(scene_file.name)
    if ref_name and raw is not None:
        matrix.committed("scene", name, ref_name, load_png(reference_path(ref_name)), to_uint8(raw))
    if name in TUTORIAL_FRAMES:
        frame = load_png(ANCHORS / TUTORIAL_FRAMES[name])
        matrix.committed("tutorial", name, name.replace("vulkan_", ""), frame[..., :3], to_uint8(ours)[..., :3],
                         "wgpu vs C++ frame")


def run_verify(out: Path, quick: bool = False) -> Report:
    """Render and compare everything (``quick``: two stages and one scene); write the outputs to ``out``."""
    from wgpurender.raw_path import reference_stage_names
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.make_references import SCENE_REFERENCES
    from wgpurender.wgpu_path.device.context import get_context

    ctx, vctx = get_context("Vulkan"), get_vulkan()
    cls = driver_class(vctx.device_name)
    info = ctx.adapter.info
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    report = Report(f"{info['device']} ({info['description']})", cpu_name(), cls, now,
                    differs=reference_difference(info.get("adapter_type")))
    matrix = Matrix(out, cls, load_table())
    stages = [s for s in reference_stage_names() if not quick or s in QUICK["stages"]]
    verify_stages(matrix, stages)
    committed = {scene: ref for ref, scene in SCENE_REFERENCES.items()}
    for scene_file in sorted(SCENE_DIR.glob("*.toml")):
        if not quick or scene_file.stem in QUICK["scenes"]:
            verify_scene(matrix, scene_file, committed)
    report.rows = matrix.rows
    write_outputs(out, report, matrix.table)
    return report


def write_outputs(out: Path, report: Report, table: dict) -> None:
    """verify.csv, verify.md and tolerances.toml, each written whole or not at all."""
    from wgpurender.core.files.safe_write import atomic_write

    text = io.StringIO(newline="")
    writer = csv.DictWriter(text, fieldnames=CSV_FIELDS)
    writer.writeheader()
    writer.writerows(r.as_csv(report.device) for r in report.rows)
    atomic_write(out / "verify.csv", text.getvalue().encode())
    atomic_write(out / "verify.md", markdown(report).encode())
    atomic_write(out / "tolerances.toml", format_table(recalibrated(table, report)).encode())


def markdown(report: Report) -> str:
    lines = [f"# wgpurender verify: {report.device}", "",
             f"- date: {report.date}", f"- CPU: {report.cpu}", f"- driver class: {report.driver_class}",
             f"- result: {len(report.failed)} of {len(report.rows)} comparisons exceed their bound",
             *([f"- unlike `render T`: {report.differs}"] if report.differs else []), "",
             "| kind | name | comparison | status | max diff | changed pixels | FLIP mean | bound | note |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in report.rows:
        m = r.metrics
        cells = ("", "", "") if m is None else (f"{m.max_abs}/255", f"{m.changed_pixels} ({100 * m.changed:.2f}%)",
                                                f"{m.flip_mean:.5f}")
        note = r.note.replace("|", "/") + (f" [heatmap]({r.heatmap})" if r.heatmap else "")
        lines.append(f"| {r.kind} | {r.name} | {r.comparison} | {r.status} | {' | '.join(cells)} | {r.bound} "
                     f"| {note} |")
    return "\n".join(lines) + "\n"


def recalibrated(table: dict, report: Report) -> dict:
    """The table with this driver class's rows re-calibrated from this run's committed comparisons."""
    import copy

    new = copy.deepcopy(table)
    cls = report.driver_class
    where = f"{report.device}, CPU {report.cpu}, {report.date}"
    info = new.setdefault("classes", {}).setdefault(cls, {})
    measured_any = False
    for row in report.rows:
        if not row.reference or row.metrics is None:
            continue
        measured_any = True
        old = new.setdefault("references", {}).setdefault(row.reference, {}).get(cls)
        bounds = calibrate([row.metrics], cls)
        text = (f"{where}: max {row.metrics.max_abs}/255, {row.metrics.changed_pixels} of {row.metrics.pixels} px "
                f"({100 * row.metrics.changed:.2f}%), FLIP {row.metrics.flip_mean:.5f}")
        if old and not old.get("provisional", False):
            bounds = {k: max(v, old[k]) for k, v in bounds.items()}
            text = f"{old.get('measured', '')}; {text}"
        kept = {k: v for k, v in (old or {}).items() if k not in (*bounds, "measured", "provisional")}
        new["references"][row.reference][cls] = {**bounds, "measured": text, **kept}  # e.g. the tutorial targets
    if measured_any and info.get("provisional"):
        info["bounded_by"] = f"{where} vs the lavapipe-made references (wgpurender verify)"
        info["provisional"] = False
    return new
