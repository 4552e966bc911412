#!/bin/sh
# Issue 31.3's load, seventh pass (load7 engineer, 2026-11-27 night), on the GPU machine, in one call of at most
# 3 minutes (the machine's start included). Run from a copy of the branch in a folder of main's checkout, with
# main's tree at 6534ca3 (its package, assets and shaders: `git archive 6534ca3 wgpurender assets shaders_wgsl
# shaders_glsl`) in a second folder beside it; the device tool carries both, and .gl/ and .whl/:
# `cd .load7 && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/load7_device_run.sh`.
# - load7 / main, warm then cold, alternating, through benchmarks/load_compare.py: 10,000 distinct mesh files
#   (warm: the parse cache filled by one untimed load first; cold: empty caches), with the split of the load's
#   functions (load_split.csv) in the first round; a second round (main first); then bench perf's batched/N scene
#   (10,000 models of one cube file, each its own transform; warm) for each tree, and a third warm round while
#   the call's time lasts (BUDGET seconds of steps).
# Few files come back from the tool: each step's log is cut to its last lines, gathered in logs.txt; the CSVs are
# printed whole at the end.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd ../.load7main && pwd)
CSV="$D/load_compare.csv"
SPLIT="$D/load_split.csv"
M="env PYTHONPATH=$MAIN:/tmp/site"
LC=benchmarks/load_compare.py
END=$(( $(date +%s) + ${BUDGET:-115} ))
timed() { if [ "$(date +%s)" -lt "$END" ]; then step "$@"; else echo "== $1: skipped (budget)" >> "$D/commands.txt"; fi; }
timed load7_warm 25 python3 $LC load7 10000 "$CSV" warm --split="$SPLIT"
timed main_warm 25 $M python3 $LC main 10000 "$CSV" warm --split="$SPLIT"
timed load7_cold 25 python3 $LC load7 10000 "$CSV" cold --split="$SPLIT"
timed main_cold 25 $M python3 $LC main 10000 "$CSV" cold --split="$SPLIT"
timed main_warm2 25 $M python3 $LC main 10000 "$CSV" warm
timed load7_warm2 25 python3 $LC load7 10000 "$CSV" warm
timed main_cold2 25 $M python3 $LC main 10000 "$CSV" cold
timed load7_cold2 25 python3 $LC load7 10000 "$CSV" cold
timed load7_batched 25 python3 $LC load7 10000 "$CSV" warm --scene=batched
timed main_batched 25 $M python3 $LC main 10000 "$CSV" warm --scene=batched
timed load7_warm3 25 python3 $LC load7 10000 "$CSV" warm
timed main_warm3 25 $M python3 $LC main 10000 "$CSV" warm
for f in "$D"/*.log; do echo "## $(basename "$f")"; tail -3 "$f"; done > /tmp/logs.txt 2>&1
rm -f "$D"/*.log; mv /tmp/logs.txt "$D/logs.txt"
cat "$D/machine.txt" "$D/commands.txt" "$CSV" "$SPLIT" "$D/logs.txt" 2>/dev/null
