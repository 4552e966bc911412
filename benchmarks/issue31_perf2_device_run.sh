#!/bin/sh
# Issue 31's second run on the GPU machine (perf2, items 6, 4 and 8): the post chain against a copy of its bytes
# at 4K, the final scene's CPU per frame, and bench perf on the Dawn binding beside wgpu-native (same flags).
# Run from the repository root with .gl/ and .whl/ carried. Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step roofline 90 python3 -m wgpurender bench post-roofline --size 3840x2160 --frames 50 --out "$D/roofline"
step scene 100 python3 -m wgpurender bench perf --only scene --out "$D/scene"
step dawn 100 env WGPURENDER_BINDING=dawn python3 -m wgpurender bench perf --only frames,scene --no-raw --no-big \
  --out "$D/dawn"
step native 80 python3 -m wgpurender bench perf --only frames,scene --no-raw --no-big --out "$D/native"
tar czf "$OUT/run.tgz" -C "$OUT" run
