#!/bin/sh
# The evening's last H100 call (integrator, 2026-11-27), on the final merged main: the whole test suite (as
# .gl/run_pytest.sh runs it, pytester loaded), then bench perf's startup and scene families on the Dawn binding
# (WGPURENDER_BINDING=dawn, wgpudawn 0.32: issue 31.8), whose first pixel the paired method had not yet measured.
# Run from the repository root with .gl/ and .whl/ carried: `sh benchmarks/evening_final_device_run.sh`.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step pytest 300 python3 -m pytest -q -p no:cacheprovider -n 15 -o addopts="" -p pytester --timeout 120 \
  --ignore tests/test_wheel.py --ignore tests/fuzz
step dawn 200 env WGPURENDER_BINDING=dawn python3 -m wgpurender bench perf --only startup,scene --out "$D/dawn"
cat "$D/commands.txt"; grep -E "^(FAILED|ERROR)" "$D/pytest.log" | cut -c1-200 | head -40; tail -3 "$D/pytest.log"
sed -n '/^## Targets/,/^## Tails/p' "$D/dawn/report.md" 2>/dev/null
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
