#!/bin/sh
# Issue 31.5 on the GPU machine (startup engineer, 2026-11-27 evening: docs/perf-h100/2026-11-27-startup2/): the
# first pixel by bench perf's startup family, the one judged method (interleaved rounds, paired wgpu/raw ratios,
# bytecode cached and not), and the wgpu child's fine marks. Run from a copy of the branch in a folder of main's
# checkout (the device tool carries main's tree; .gl/ and .whl/ beside, linked into the copy):
# `cd .startup && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/startup_device_run.sh`.
# - perf: `bench perf --only startup` (rows with and without cached bytecode, and without the drivers' preload);
# - phases: benchmarks/first_pixel_phases.py: where the wgpu child's time goes after start_context.
# Writes everything under $OUT/run. (The afternoon's batch, docs/perf-h100/2026-11-27-startup/, ran
# startup_split.py, which this branch removed: bench perf's family replaced it.)
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step perf 130 python3 -m wgpurender bench perf --only startup --out "$D/perf"
step phases 25 python3 benchmarks/first_pixel_phases.py 7 "$D/first_pixel_phases.csv"
cat "$D/commands.txt"
grep -E "startup:" "$D/perf.log"; sed -n '/^## Targets/,/^## /p' "$D/perf/report.md" | grep -i "first pixel"
cat "$D/phases.log"
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
