"""Re-calibrate the wgpu-gl and browser rows of assets/reference/implementations.toml from measured.csv (the
baseline rows: each implementation against wgpu-vulkan at every size recorded), with this run's provenance.

    PYTHONPATH=. python docs/runs/2026-11-27-size-free-bounds/calibrate.py
"""

import csv
from pathlib import Path

from wgpurender.core.verdict.structure import Structure
from wgpurender.core.verdict.tolerances import IMPLEMENTATIONS_PATH, Metrics, format_implementation_table, load_table
from wgpurender.implementations import calibrate

RUN = Path(__file__).parent
WHO = {"wgpu-gl": "llvmpipe (LLVM 15.0.6, 256 bits) (OpenGL, CPU, 4.5 (Core Profile) Mesa 22.3.6) (wgpu-native, "
                  "child process)", "browser": "Chrome/156.0.8078.108 / google swiftshader"}
VS = "llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, CPU, Mesa 22.3.6 (LLVM 15.0.6)), CPU AMD EPYC"

rows = list(csv.DictReader((RUN / "measured.csv").open()))
before = load_table(IMPLEMENTATIONS_PATH)["implementations"]
for impl, who in WHO.items():
    measured = {}
    for r in rows:
        if r["kind"] == "baseline" and r["impl"] == impl:
            m = Metrics(int(r["max_abs"]), float(r["changed"]), int(r["changed_pixels"]), float(r["flip_mean"]),
                        int(r["pixels"]))
            measured.setdefault(r["size"], {})[r["target"]] = (m, Structure(float(r["radial"]), float(r["detail"])))
    sizes = ", ".join(measured)
    calibrate(impl, measured, f"{who} vs {VS}, {sizes}, {(RUN / 'machine.txt').read_text().splitlines()[0]} "
              f"(docs/runs/{RUN.name}: record.py, measure.py, calibrate.py)", "lavapipe")
table = load_table(IMPLEMENTATIONS_PATH)
for impl in WHO:  # targets this run did not draw (clear; the tutorial scenes need shared/anchors): old rows kept
    targets = table["implementations"][impl]["targets"]
    for name, row in before[impl]["targets"].items():
        if name not in targets:
            targets[name] = {**row, "measured": row["measured"] + f" (160x120 only: docs/runs/{RUN.name} did "
                             "not draw it)"}
IMPLEMENTATIONS_PATH.write_text(format_implementation_table(table))
