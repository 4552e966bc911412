#!/bin/sh
# Issue 31.3's load, second pass (load engineer, 2026-11-27 evening), on the GPU machine. Run from a copy of the
# branch in a folder of main's checkout (the device tool carries main's tree; .gl/ and .whl/ beside, linked into
# the copy): `cd .load && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/load2_device_run.sh`.
# - load_warm, load_cold: this branch, 10,000 distinct mesh files, parse caches filled / empty, with the split of
#   the load's functions (load_split.csv);
# - main_warm, main_cold: main's tree (the folder above) through this branch's script, same split where main has
#   the function;
# - tests: the load tests on the GPU (shared buffers, base vertex, workers, the TOML cache, instancing);
# - fork_probe: what forking 16 workers costs in a process holding the device;
# - load_warm_8: this branch with the worker rule's cap at 8 instead of 16 (fewer forks, less parallel reading).
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
CSV="$D/load_compare.csv"
SPLIT="$D/load_split.csv"
step load_warm 30 python3 benchmarks/load_compare.py load2 10000 "$CSV" warm --split="$SPLIT"
step load_cold 25 python3 benchmarks/load_compare.py load2 10000 "$CSV" cold --split="$SPLIT"
step main_warm 35 env PYTHONPATH="$MAIN:/tmp/site" python3 benchmarks/load_compare.py main 10000 "$CSV" warm \
  --split="$SPLIT"
step main_cold 25 env PYTHONPATH="$MAIN:/tmp/site" python3 benchmarks/load_compare.py main 10000 "$CSV" cold
step tests 45 python3 -m pytest -q -x -p no:cacheprovider tests/test_scene_load_scale.py tests/test_scene_toml_cache.py \
  tests/test_mesh_workers.py tests/test_shared_mesh_buffers.py tests/test_instancing.py
step fork_probe 15 python3 benchmarks/fork_cost_probe.py 16
step load_warm_8 25 python3 benchmarks/load_compare.py load2 10000 "$CSV" warm --max-workers=8 --split="$SPLIT"
(cd "$MAIN" && git log -1 --format='main %H %cI' 2>/dev/null) >> "$D/machine.txt"
cat "$D/commands.txt" "$CSV" "$SPLIT" "$D/fork_probe.log" 2>/dev/null; tail -3 "$D/tests.log"
