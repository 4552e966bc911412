#!/bin/sh
# Issue 31.4's passes pass on the GPU machine (passes engineer, 2026-11-27). Run from a copy of the branch in a
# folder of main's checkout (the device tool carries main's tree; .gl/ and .whl/ beside, linked into the copy):
# `cd .passes && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/passes_device_run.sh`.
# - scene_main_N, scene_passes_N: `bench perf --only scene --no-raw`, main's tree (the folder above) and this one
#   in alternating rounds on one host (the final scene's cpu_ms:untimed rows, one offscreen target);
# - frame_python.csv: benchmarks/frame_python_probe.py (this tree's probe, either tree's renderer) at 1920x1080,
#   each frame into a new texture (a window's swapchain) and into one target, main and this tree in turn.
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
HERE=$(pwd)
PROBE="$HERE/benchmarks/frame_python_probe.py"
for r in 1 2; do
  # python -m puts the working folder first on sys.path: main's run starts in main's folder
  step "scene_main_$r" 40 sh -c "cd '$MAIN' && PYTHONPATH='$MAIN:/tmp/site' python3 -m wgpurender bench perf \
    --only scene --no-raw --out '$D/scene_main_$r'"
  step "scene_passes_$r" 40 python3 -m wgpurender bench perf --only scene --no-raw --out "$D/scene_passes_$r"
done
for mode in new same; do
  step "probe_main_$mode" 30 sh -c "cd '$MAIN' && PYTHONPATH='$MAIN:/tmp/site' python3 '$PROBE' \
    '$D/frame_python.csv' main final.toml 1920x1080 300 $mode"
  step "probe_passes_$mode" 30 python3 "$PROBE" "$D/frame_python.csv" passes final.toml 1920x1080 300 $mode
done
cat "$D/commands.txt" "$D/frame_python.csv" | cut -c1-160
for f in "$D"/scene_*/results.csv; do echo "$f"; grep "cpu_ms:untimed" "$f" | cut -d, -f2,4,6,11; done
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
