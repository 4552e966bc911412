#!/bin/sh
# Issue 31.3's load run on the GPU machine (load engineer, 2026-11-27). Run from a copy of the branch in a folder
# of main's checkout (the device tool carries main's tree; .gl/ and .whl/ beside, linked into the copy):
# `cd .load && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/load_device_run.sh`.
# - load_main: main's tree (the folder above), 10,000 distinct mesh files, through this branch's script;
# - load_cold, load_warm: this branch, parse cache empty / filled, the plan's worker processes (auto);
# - load_cold_off, load_warm_off: the same with mesh_workers=off (this process parses or reads every file);
# - tests: the load tests and the shared-buffer / instancing tests on the GPU (base vertex as NVIDIA takes it);
# - cull_probe: a GPU-culled draw after another draw (benchmarks/cull_order_probe.py: copies lost on lavapipe).
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
CSV="$D/load_compare.csv"
step load_main 30 env PYTHONPATH="$MAIN:/tmp/site" python3 benchmarks/load_compare.py main 10000 "$CSV" cold
step load_cold 25 python3 benchmarks/load_compare.py load 10000 "$CSV" cold
step load_warm 30 python3 benchmarks/load_compare.py load 10000 "$CSV" warm
step load_cold_off 25 python3 benchmarks/load_compare.py load 10000 "$CSV" cold mesh_workers=off
step load_warm_off 30 python3 benchmarks/load_compare.py load 10000 "$CSV" warm mesh_workers=off
step tests 50 python3 -m pytest -q -x -p no:cacheprovider tests/test_mesh_workers.py tests/test_mesh_parse_cache.py \
  tests/test_scene_load_scale.py tests/test_shared_mesh_buffers.py tests/test_instancing.py
step cull_probe 20 python3 benchmarks/cull_order_probe.py
cat "$D/commands.txt" "$CSV" "$D/cull_probe.log" 2>/dev/null; tail -3 "$D/tests.log"
