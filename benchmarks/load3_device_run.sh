#!/bin/sh
# Issue 31.3's load, third pass (load3 engineer, 2026-11-27 evening), on the GPU machine, in one call of at most
# 3 minutes. Run from a copy of the branch in a folder of main's checkout (the device tool carries main's tree;
# .gl/ and .whl/ beside, linked into the copy):
# `cd .load3 && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/load3_device_run.sh`.
# - load3 / main, warm then cold, alternating: 10,000 distinct mesh files through benchmarks/load_compare.py,
#   parse caches filled / empty (cold is what bench perf's scene-scale row meets on a fresh machine), with the
#   split of the load's functions (load_split.csv);
# - tests: the workers-ahead tests and the load tests on the GPU (same meshes, same image, the refusal);
# - a second warm round of each tree, if the time is left, for the host's spread.
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
CSV="$D/load_compare.csv"
SPLIT="$D/load_split.csv"
step load3_warm 25 python3 benchmarks/load_compare.py load3 10000 "$CSV" warm --split="$SPLIT"
step main_warm 25 env PYTHONPATH="$MAIN:/tmp/site" python3 benchmarks/load_compare.py main 10000 "$CSV" warm \
  --split="$SPLIT"
step load3_cold 20 python3 benchmarks/load_compare.py load3 10000 "$CSV" cold --split="$SPLIT"
step main_cold 20 env PYTHONPATH="$MAIN:/tmp/site" python3 benchmarks/load_compare.py main 10000 "$CSV" cold \
  --split="$SPLIT"
step tests 25 python3 -m pytest -q -x -p no:cacheprovider tests/test_mesh_workers_ahead.py tests/test_mesh_workers.py \
  tests/test_shared_mesh_buffers.py
step load3_warm2 20 python3 benchmarks/load_compare.py load3 10000 "$CSV" warm
step main_warm2 20 env PYTHONPATH="$MAIN:/tmp/site" python3 benchmarks/load_compare.py main 10000 "$CSV" warm
(cd "$MAIN" && git log -1 --format='main %H %cI' 2>/dev/null) >> "$D/machine.txt"
cat "$D/commands.txt" "$CSV" "$SPLIT" 2>/dev/null; tail -3 "$D/tests.log"
