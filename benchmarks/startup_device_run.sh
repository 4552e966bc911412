#!/bin/sh
# Issue 31.5 and 31.4 on the GPU machine (startup engineer, 2026-11-27): the first pixel with the device made on a
# thread, and the frame rows' tails. Run from a copy of the branch in a folder of main's checkout (the device tool
# carries main's tree; .gl/ and .whl/ beside, linked into the copy):
# `cd .startup && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/startup_device_run.sh`.
# - perf: `bench perf --only startup,frames,scene` of this branch: the first pixel with bytecode cached ("no
#   caches") and without ("no caches, no bytecode"), and the frame rows whose p99 is judged;
# - split: benchmarks/startup_split.py: the wgpu phases with the device made early / in order, and raw;
# - tails: benchmarks/tail_probe.py: every timed frame of five cases with its place in the rounds;
# - profile: benchmarks/first_pixel_profile.py (cProfile of each path's child; this machine compiles bytecode
#   afresh in every process);
# - perf_main: the same bench perf of main's tree (the folder above), same machine, for comparison.
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
step perf 100 python3 -m wgpurender bench perf --only startup,frames,scene --out "$D/perf"
step split 40 python3 benchmarks/startup_split.py 9 "$D/startup_split.csv"
step tails 35 python3 benchmarks/tail_probe.py "$D/tail_probe.csv" 100
step profile 20 python3 benchmarks/first_pixel_profile.py "$D/profile"
step perf_main 80 env PYTHONPATH="$MAIN:/tmp/site" python3 -m wgpurender bench perf --only startup,frames,scene \
  --out "$D/perf_main"
cat "$D/commands.txt"
grep -E "startup: (wgpu|raw) no caches(, no bytecode)?:" "$D/perf.log" "$D/perf_main.log"
tail -8 "$D/split.log"; cut -c1-230 "$D/tails.log" | tail -10
sed -n '/^## Targets/,/^## Tails/p' "$D/perf/report.md" "$D/perf_main/report.md" 2>/dev/null | head -40
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"  # the tool returns at most 8 files
