#!/bin/sh
# Issue 31.4's frame4 pass on the GPU machine (frame4 engineer, 2026-11-27): does recording the next frame ahead
# (FramesAhead, benchmarks/record_ahead_probe.py) or pinning the thread cut the final scene's CPU per frame? Run
# from a copy of the branch in a folder of main's checkout, .gl/ and .whl/ carried beside it:
# `cd .frame4 && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/frame4_device_run.sh`.
# - probe_1, probe_2: benchmarks/record_ahead_probe.py at 800x600..3840x2160, two processes (each: today's
#   structure, record-ahead, and both with the thread pinned, in alternating rounds; every CPU span timed);
# - scene: `bench perf --only scene --no-raw` (the judged cpu_ms:untimed rows, as the bench draws them now).
# The second call (PROBE=cold): benchmarks/cold_frame_probe.py instead (today's frame, record-ahead, the same
# native calls replayed without Python, and a wait in naps), one process.
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
if [ "${PROBE:-}" = cold ]; then
  step cold 120 python3 benchmarks/cold_frame_probe.py "$D/cold_frame_probe.csv" final.toml \
    800x600,1280x720,1920x1080,3840x2160 400 4
  cat "$D/commands.txt" "$D/cold_frame_probe.csv"
  tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
  exit 0
fi
for r in 1 2; do
  step "probe_$r" 60 python3 benchmarks/record_ahead_probe.py "$D/record_ahead_probe_$r.csv" final.toml \
    800x600,1280x720,1920x1080,3840x2160 400 4
done
step scene 60 python3 -m wgpurender bench perf --only scene --no-raw --out "$D/scene"
cat "$D/commands.txt"; cut -d, -f1-13 "$D"/record_ahead_probe_*.csv
grep -h "cpu_ms:untimed" "$D/scene/results.csv" | cut -d, -f2,4,6,11
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
