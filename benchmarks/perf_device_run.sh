#!/bin/sh
# Issue 31's third run on the GPU machine (perf engineer, 2026-11-27): why CPU per frame grows with the instance
# count (benchmarks/cpu_growth_probe.py), the whole `bench perf` after the load and CPU changes, and Dawn's first
# pixel (the startup family on WGPURENDER_BINDING=dawn; wgpu-native's is in the perf run of the same call).
# Run from the repository root with .gl/ and .whl/ carried. Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step probe 90 python3 benchmarks/cpu_growth_probe.py "$D/cpu_growth_probe.csv"
step perf 300 python3 -m wgpurender bench perf --out "$D/perf"
step dawn 120 env WGPURENDER_BINDING=dawn python3 -m wgpurender bench perf --only startup --no-raw --out "$D/dawn"
tar czf "$OUT/run.tgz" -C "$OUT" run
