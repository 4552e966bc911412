#!/bin/sh
# Issue 31.5 and 31.4 on the GPU machine (startup engineer, 2026-11-27): the first pixel with the device made on a
# thread, and the frame rows' tails. Run from a copy of the branch in a folder of main's checkout (the device tool
# carries main's tree; .gl/ and .whl/ beside, linked into the copy):
# `cd .startup && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/startup_device_run.sh`.
# - startup, startup_main: `bench perf --only startup` of this branch, then of main's tree (the folder above),
#   same machine: the first pixel with bytecode cached ("no caches") and without ("no caches, no bytecode");
# - split: benchmarks/startup_split.py: the wgpu phases with the device made early / in order, and raw;
# - profile: benchmarks/first_pixel_profile.py (cProfile of each path's child);
# - tails: benchmarks/tail_probe.py: every timed frame of five cases with its place in the rounds;
# - perf, perf_main: `bench perf --only frames,scene` of this branch, then of main's tree (the p99 rows).
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
step startup 55 python3 -m wgpurender bench perf --only startup --out "$D/startup"
step startup_main 55 env PYTHONPATH="$MAIN:/tmp/site" python3 -m wgpurender bench perf --only startup --out "$D/startup_main"
step split 40 python3 benchmarks/startup_split.py 9 "$D/startup_split.csv"
step profile 20 python3 benchmarks/first_pixel_profile.py "$D/profile"
step tails 25 python3 benchmarks/tail_probe.py "$D/tail_probe.csv" 100
step perf 60 python3 -m wgpurender bench perf --only frames,scene --out "$D/perf"
step perf_main 45 env PYTHONPATH="$MAIN:/tmp/site" python3 -m wgpurender bench perf --only frames,scene --out "$D/perf_main"
cat "$D/commands.txt"
grep -E "startup: (wgpu|raw) no caches(, no bytecode)?:" "$D/startup.log" "$D/startup_main.log"
cat "$D/split.log" "$D/tails.log" 2>/dev/null | tail -25
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"  # the tool returns at most 8 files
