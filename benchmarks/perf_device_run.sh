#!/bin/sh
# Issue 31's third run on the GPU machine (perf engineer, 2026-11-27). Run from a copy of the branch in a folder
# of main's checkout (the device tool carries main's tree; .gl/ and .whl/ beside, linked into the copy):
# `cd .perf && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/perf_device_run.sh`.
# - probe, probe_dawn: why CPU per frame grows with the instance count (benchmarks/cpu_growth_probe.py), on
#   wgpu-native and on Dawn;
# - load_main, load_perf: the 10k-distinct-mesh load of main's tree (the folder above) and of this one, same call;
# - tests: the shared mesh buffers, instancing and culling on the GPU (offsets as NVIDIA's driver takes them);
# - dawn: Dawn's first pixel (the startup family on WGPURENDER_BINDING=dawn; wgpu-native's is in the perf step);
# - perf: `bench perf` of the families the issue judges (frames, scene, scene-scale, startup).
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
step probe 50 python3 benchmarks/cpu_growth_probe.py "$D/cpu_growth_probe.csv"
step probe_dawn 40 env WGPURENDER_BINDING=dawn python3 benchmarks/cpu_growth_probe.py "$D/cpu_growth_probe_dawn.csv"
step load_main 50 env PYTHONPATH="$MAIN:/tmp/site" python3 benchmarks/load_compare.py main 10000 "$D/load_compare.csv"
step load_perf 30 python3 benchmarks/load_compare.py perf 10000 "$D/load_compare.csv"
step tests 60 python3 -m pytest -q -p no:cacheprovider tests/test_shared_mesh_buffers.py tests/test_instancing.py \
  tests/test_culling.py tests/test_obj_simple.py
step dawn 70 env WGPURENDER_BINDING=dawn python3 -m wgpurender bench perf --only startup --no-raw --out "$D/dawn"
step perf 270 python3 -m wgpurender bench perf --only frames,scene,scene-scale,startup --out "$D/perf"
cat "$D/commands.txt" "$D/cpu_growth_probe.csv" "$D/cpu_growth_probe_dawn.csv" "$D/load_compare.csv" 2>/dev/null
sed -n '/^## Targets/,/^## Tails/p' "$D/perf/report.md" 2>/dev/null  # the reply's tail: the run at a glance
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"  # the tool returns at most 8 files
