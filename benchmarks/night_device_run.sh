#!/bin/sh
# The night's closing H100 calls for issue 31 (integrator, 2026-11-27), on main with the post4, load4, frame4,
# post5 and load5 branches merged. MODE scale: bench perf's scene-scale and startup families and frame4's replay
# probe (benchmarks/cold_frame_probe.py: does the final scene's frame without Python fit 0.3 ms at 4K?). MODE frames:
# bench perf's frames and scene families, then the whole suite (pytester loaded, the wheel and fuzz tests left out,
# as .gl/run_pytest.sh does). MODE load: where a cold 10k distinct-file load goes now (benchmarks/load_compare.py,
# cold and warm with the split, two rounds) and with fewer worker processes (--max-workers 15 and 8, cold).
# Each mode is one call (at most 10 minutes). Run from the repository root with .gl/ and .whl/ carried:
# `sh benchmarks/night_device_run.sh MODE`. Writes $OUT/run.tgz.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
if [ "${1:-}" = load ]; then
  for r in 1 2; do
    step "cold_$r" 30 python3 benchmarks/load_compare.py main 10000 "$D/load_compare.csv" cold --split="$D/load_split.csv"
    step "warm_$r" 30 python3 benchmarks/load_compare.py main 10000 "$D/load_compare.csv" warm --split="$D/load_split.csv"
    step "cold_15_$r" 30 python3 benchmarks/load_compare.py workers15 10000 "$D/load_compare.csv" cold --max-workers=15
    step "cold_8_$r" 30 python3 benchmarks/load_compare.py workers8 10000 "$D/load_compare.csv" cold --max-workers=8
  done
  for f in "$D"/*.log; do echo "## $(basename "$f")"; tail -3 "$f"; done > "$D/logs.txt" 2>&1; rm -f "$D"/*.log
  cat "$D/commands.txt" "$D/load_compare.csv"
elif [ "${1:-}" = scale ]; then
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
