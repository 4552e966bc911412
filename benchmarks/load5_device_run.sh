#!/bin/sh
# Issue 31.3's load, fifth pass (load5 engineer, 2026-11-27 night), on the GPU machine, in one call of at most
# 3 minutes (the machine's start included). Run from a copy of the branch in a folder of main's checkout (the
# device tool carries main's tree; .gl/ and .whl/ beside, linked into the copy):
# `cd .load5 && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/load5_device_run.sh`.
# - load5 / main, cold then warm, alternating: 10,000 distinct mesh files through benchmarks/load_compare.py
#   (cold: empty caches, what bench perf's scene-scale row meets on a fresh machine), with the split of the
#   load's functions (load_split.csv) in the first round; a second round of each;
# - this pass's tests on the GPU machine.
# Few files come back from the tool (8 of 16 did for load4): each step's log is cut to its last lines, gathered in
# logs.txt; the CSVs are printed whole at the end.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
CSV="$D/load_compare.csv"
SPLIT="$D/load_split.csv"
M="env PYTHONPATH=$MAIN:/tmp/site"
step load5_cold 25 python3 benchmarks/load_compare.py load5 10000 "$CSV" cold --split="$SPLIT"
step main_cold 25 $M python3 benchmarks/load_compare.py main 10000 "$CSV" cold --split="$SPLIT"
step load5_warm 25 python3 benchmarks/load_compare.py load5 10000 "$CSV" warm --split="$SPLIT"
step main_warm 25 $M python3 benchmarks/load_compare.py main 10000 "$CSV" warm --split="$SPLIT"
step tests 30 python3 -m pytest -q -p no:cacheprovider tests/test_load_arrays.py
step main_cold2 20 $M python3 benchmarks/load_compare.py main 10000 "$CSV" cold
step load5_cold2 20 python3 benchmarks/load_compare.py load5 10000 "$CSV" cold
step main_warm2 20 $M python3 benchmarks/load_compare.py main 10000 "$CSV" warm
step load5_warm2 20 python3 benchmarks/load_compare.py load5 10000 "$CSV" warm
(cd "$MAIN" && git log -1 --format='main %H %cI' 2>/dev/null) >> "$D/machine.txt"
for f in "$D"/*.log; do echo "## $(basename "$f")"; tail -4 "$f"; done > /tmp/logs.txt 2>&1
rm -f "$D"/*.log; mv /tmp/logs.txt "$D/logs.txt"
cat "$D/machine.txt" "$D/commands.txt" "$CSV" "$SPLIT" "$D/logs.txt" 2>/dev/null
