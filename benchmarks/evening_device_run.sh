#!/bin/sh
# The evening's closing H100 call for issue 31 (integrator, 2026-11-27), on main with the startup, post, frametime,
# load and passes branches merged: bench perf's families whose goals the issue names, in two invocations so that a
# time limit loses at most one report: scene-scale and startup (instances beside pygfx, distinct files' load, the
# same-wait CPU row, first pixel), then frames and scene (p99 <= 2x the median, the final scene's CPU per frame).
# Run from the repository root with .gl/ and .whl/ carried: `sh benchmarks/evening_device_run.sh`. Writes $OUT/run.tgz.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step scale 300 python3 -m wgpurender bench perf --only scene-scale,startup --out "$D/perf-scale"
step frames 230 python3 -m wgpurender bench perf --only frames,scene --out "$D/perf-frames"
cat "$D/commands.txt"
for r in perf-scale perf-frames; do sed -n '/^## Targets/,/^## Tails/p' "$D/$r/report.md" 2>/dev/null; done
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
