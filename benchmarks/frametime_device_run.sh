#!/bin/sh
# Issue 31.3/31.4's frametime pass on the GPU machine (frametime engineer, 2026-11-27). Run from a copy of the
# branch in a folder of main's checkout (the device tool carries main's tree; .gl/ and .whl/ beside, linked into
# the copy): `cd .frametime && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/frametime_device_run.sh`.
# - probe: record + submit after each wait, the CPU each wait burns, every native call at spin (cpu_growth_probe.py);
# - tails: what each slow frame was doing (tail_cause_probe.py);
# - scene_main, scene_frametime: the scene family without the raw peer, main's tree (the folder above) then this
#   one, back to back (the final scene's CPU per frame before and after the bound frames, one host);
# - perf: `bench perf --only frames,scene-scale` (the frame rows' p99, the same-wait growth row; the scene family is
#   the step before, without the raw peer, to fit the call in the 6 minutes this pass was given).
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
step probe 40 python3 benchmarks/cpu_growth_probe.py "$D/cpu_growth_probe.csv" 1000,10000,16384,100000,1000000 30
step tails 30 python3 benchmarks/tail_cause_probe.py "$D/tail_cause_probe.csv" 150
# python -m puts the working folder first on sys.path: main's run starts in main's folder
step scene_main 30 sh -c "cd '$MAIN' && PYTHONPATH='$MAIN:/tmp/site' python3 -m wgpurender bench perf --only scene \
  --no-raw --out '$D/scene_main'"
step scene_frametime 30 python3 -m wgpurender bench perf --only scene --no-raw --out "$D/scene_frametime"
step perf 130 python3 -m wgpurender bench perf --only frames,scene-scale --out "$D/perf"
cat "$D/commands.txt" "$D/cpu_growth_probe.csv"; tail -9 "$D/tails.log"
grep -h "cpu_ms:untimed" "$D/scene_main/results.csv" "$D/scene_frametime/results.csv" | cut -d, -f2,4,6,11
sed -n '/^## Targets/,/^## Tails/p' "$D/perf/report.md" 2>/dev/null  # the reply's tail: the run at a glance
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
