#!/bin/sh
# Issue 31.3's load, fourth pass (load4 engineer, 2026-11-27 night), on the GPU machine, in one call of at most
# 4 minutes. Run from a copy of the branch in a folder of main's checkout (the device tool carries main's tree;
# .gl/ and .whl/ beside, linked into the copy):
# `cd .load4 && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/load4_device_run.sh`.
# - load4 / main, cold then warm, alternating: 10,000 distinct mesh files through benchmarks/load_compare.py
#   (cold: empty parse cache, what bench perf's scene-scale row meets on a fresh machine), with the split of the
#   load's functions (load_split.csv) in the first round;
# - where a worker's cold file goes: benchmarks/worker_cold_probe.py for each tree (per-file steps in one process,
#   16 processes writing 10,000 per-file entries into one folder, the workers' reading cold and warm);
# - the workers' tests on the GPU; a second cold / warm round of each tree if the time is left.
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
CSV="$D/load_compare.csv"
SPLIT="$D/load_split.csv"
PROBE="$D/worker_probe.csv"
M="env PYTHONPATH=$MAIN:/tmp/site"
step load4_cold 25 python3 benchmarks/load_compare.py load4 10000 "$CSV" cold --split="$SPLIT"
step main_cold 25 $M python3 benchmarks/load_compare.py main 10000 "$CSV" cold --split="$SPLIT"
step load4_warm 25 python3 benchmarks/load_compare.py load4 10000 "$CSV" warm --split="$SPLIT"
step main_warm 25 $M python3 benchmarks/load_compare.py main 10000 "$CSV" warm --split="$SPLIT"
step load4_probe 25 python3 benchmarks/worker_cold_probe.py load4 10000 16 "$PROBE"
step main_probe 30 $M python3 benchmarks/worker_cold_probe.py main 10000 16 "$PROBE"
step tests 30 python3 -m pytest -q -p no:cacheprovider tests/test_mesh_workers.py tests/test_mesh_workers_ahead.py \
  tests/test_mesh_chunk_cache.py
step load4_cold2 20 python3 benchmarks/load_compare.py load4 10000 "$CSV" cold
step main_cold2 20 $M python3 benchmarks/load_compare.py main 10000 "$CSV" cold
step load4_warm2 20 python3 benchmarks/load_compare.py load4 10000 "$CSV" warm
step main_warm2 20 $M python3 benchmarks/load_compare.py main 10000 "$CSV" warm
(cd "$MAIN" && git log -1 --format='main %H %cI' 2>/dev/null) >> "$D/machine.txt"
cat "$D/commands.txt" "$CSV" "$PROBE" 2>/dev/null; tail -3 "$D/tests.log"
