#!/bin/sh
# Issue 31.3's load, eighth pass (load8 engineer, 2026-11-27 late): the mesh workers as fresh interpreters booted
# while the scene is checked, against main's forked workers (branch commit 7b5f49c; the fresh workers and
# their tests were reverted after this call: docs/perf-h100/2026-11-27-load8/README.md says why), on the GPU
# machine in one call of at most 3 minutes (the machine's start included). Run from a copy of the branch in a folder of main's checkout, with main's tree
# (`git archive main wgpurender assets/textures shaders_wgsl`) in a second folder beside it; the device tool
# carries both, and .gl/ and .whl/: `cd .load8 && ln -s ../.gl .gl && ln -s ../.whl .whl && sh
# benchmarks/load8_device_run.sh`.
# - load8 / main, cold then warm, alternating, through benchmarks/load_compare.py (10,000 distinct mesh files;
#   cold: empty caches; warm: the parse cache filled by one untimed load first), the split of the load's functions
#   (load_split.csv) in the first round; a second round (main first); bench perf's batched/N scene (the issue's
#   own, one cube file: no workers booted) for each tree; the worker tests; then the worker processes left
#   running (none expected), while the call's time lasts (BUDGET seconds of steps).
# Few files come back from the tool: each step's log is cut to its last lines, gathered in logs.txt; the CSVs are
# printed whole at the end.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd ../.load8main && pwd)
CSV="$D/load_compare.csv"
SPLIT="$D/load_split.csv"
M="env PYTHONPATH=$MAIN:/tmp/site"
LC=benchmarks/load_compare.py
END=$(( $(date +%s) + ${BUDGET:-100} ))
timed() { if [ "$(date +%s)" -lt "$END" ]; then step "$@"; else echo "== $1: skipped (budget)" >> "$D/commands.txt"; fi; }
timed load8_cold 25 python3 $LC load8 10000 "$CSV" cold --split="$SPLIT"
timed main_cold 25 $M python3 $LC main 10000 "$CSV" cold --split="$SPLIT"
timed load8_warm 25 python3 $LC load8 10000 "$CSV" warm --split="$SPLIT"
timed main_warm 25 $M python3 $LC main 10000 "$CSV" warm --split="$SPLIT"
timed main_cold2 25 $M python3 $LC main 10000 "$CSV" cold
timed load8_cold2 25 python3 $LC load8 10000 "$CSV" cold
timed main_warm2 25 $M python3 $LC main 10000 "$CSV" warm
timed load8_warm2 25 python3 $LC load8 10000 "$CSV" warm
timed load8_batched 25 python3 $LC load8 10000 "$CSV" warm --scene=batched
timed main_batched 25 $M python3 $LC main 10000 "$CSV" warm --scene=batched
timed tests 40 python3 -m pytest -q -p no:cacheprovider -o addopts="" tests/test_mesh_worker_processes.py \
  tests/test_mesh_workers.py
echo "worker processes left running: $(ps -eo args | grep -c '[m]esh_worker_main')" >> "$D/commands.txt"
for f in "$D"/*.log; do echo "## $(basename "$f")"; tail -3 "$f"; done > /tmp/logs.txt 2>&1
rm -f "$D"/*.log; mv /tmp/logs.txt "$D/logs.txt"
cat "$D/machine.txt" "$D/commands.txt" "$CSV" "$SPLIT" "$D/logs.txt" 2>/dev/null
