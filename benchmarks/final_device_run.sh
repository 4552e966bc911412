#!/bin/sh
# The afternoon's closing H100 call (integrator, 2026-11-27): the whole test suite on main (as
# .gl/run_pytest.sh does it), then bench perf's frames, scene and startup families, the families whose
# figures the afternoon's branches changed (bench method, the sRGB twin, the startup thread).
# Run from the repository root with .gl/ and .whl/ carried: `sh benchmarks/final_device_run.sh`. Writes $OUT/run.tgz.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step pytest 290 python3 -m pytest -q -p no:cacheprovider -n 15 -o addopts="" --timeout 120 \
  --ignore tests/test_wheel.py --ignore tests/fuzz
step perf 250 python3 -m wgpurender bench perf --only frames,scene,startup --out "$D/perf"
cat "$D/commands.txt"; grep -E "^(FAILED|ERROR)" "$D/pytest.log" | cut -c1-200 | head -40; tail -3 "$D/pytest.log"
sed -n '/^## Targets/,/^## Tails/p' "$D/perf/report.md" 2>/dev/null
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
