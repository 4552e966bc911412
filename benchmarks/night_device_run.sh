#!/bin/sh
# The night's closing H100 calls for issue 31 (integrator, 2026-11-27), on main with the post4, load4, frame4,
# post5 and load5 branches merged. MODE scale: bench perf's scene-scale and startup families and frame4's replay
# probe (benchmarks/cold_frame_probe.py: does the final scene's frame without Python fit 0.3 ms at 4K?). MODE frames:
# bench perf's frames and scene families, then the whole suite (pytester loaded, the wheel and fuzz tests left out,
# as .gl/run_pytest.sh does). Each mode is one call (at most 10 minutes). Run from the repository root with .gl/ and .whl/ carried:
# `sh benchmarks/night_device_run.sh MODE`. Writes $OUT/run.tgz.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
if [ "${1:-}" = scale ]; then
  step scale 300 python3 -m wgpurender bench perf --only scene-scale,startup --out "$D/perf-scale"
  step cold 120 python3 benchmarks/cold_frame_probe.py "$D/cold_frame_probe.csv" final.toml \
    800x600,1280x720,1920x1080,3840x2160 400 4
  cat "$D/commands.txt"; sed -n '/^## Targets/,/^## Tails/p' "$D/perf-scale/report.md" 2>/dev/null
  cut -c1-200 "$D/cold_frame_probe.csv"
else
  step frames 230 python3 -m wgpurender bench perf --only frames,scene --out "$D/perf-frames"
  step tests 320 python3 -m pytest -q -p no:cacheprovider -n 15 -o addopts="" -p pytester --timeout 120 \
    --ignore tests/test_wheel.py --ignore tests/fuzz
  cat "$D/commands.txt"; sed -n '/^## Targets/,/^## Tails/p' "$D/perf-frames/report.md" 2>/dev/null
  grep -E "^(FAILED|ERROR)" "$D/tests.log" | cut -c1-200 | head -30; tail -3 "$D/tests.log"
fi
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
