#!/bin/sh
# Issue 31's run on the GPU machine (the device tool): run from the repository root with .gl/ and .whl/ carried
# (docs/perf-h100/2026-11-27-issue31/README.md lists what each file is). Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step tests 120 python3 -m pytest -q -p no:cacheprovider tests/test_instancing.py tests/test_culling.py \
  tests/test_binding.py tests/test_plan_is_what_is_built.py
step perf 330 python3 -m wgpurender bench perf --out "$D/perf"
step dawn 100 env WGPURENDER_BINDING=dawn python3 -m wgpurender bench perf --only frames,scene,startup --no-raw \
  --no-big --out "$D/dawn"
step matrix 100 python3 -m wgpurender verify --implementations raw,wgpu-vulkan,wgpu-dawn --out "$D/matrix"
step explain 30 python3 -m wgpurender render assets/scenes/final.toml --explain --size 3840x2160
tar czf "$OUT/run.tgz" -C "$OUT" run
