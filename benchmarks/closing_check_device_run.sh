#!/bin/sh
# The closing check on the H100 (integrator, 2026-11-27), after the fixes the closing call found: the test files it
# failed, with the culling and animation tests (pytester loaded, as .gl/run_pytest.sh does), then bench perf's
# frames and scene families again (the garbage collector's freeze now works on the machine's Python 3.12).
# Run from the repository root with .gl/ and .whl/ carried: `sh benchmarks/closing_check_device_run.sh`.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step tests 150 python3 -m pytest -q -p no:cacheprovider -n 15 -o addopts="" -p pytester --timeout 120 \
  tests/test_early_context.py tests/test_window_gc.py tests/test_instance_data.py tests/test_clearcoat.py \
  tests/test_concepts.py tests/test_concepts_calls.py tests/test_culling.py tests/test_gltf_animation.py \
  tests/test_gltf_cameras.py tests/test_loud_checks.py tests/test_post_paths.py tests/test_post_intermediate.py
step perf 200 python3 -m wgpurender bench perf --only frames,scene --out "$D/perf"
cat "$D/commands.txt"; tail -4 "$D/tests.log"
sed -n '/^## Targets/,/^## Tails/p' "$D/perf/report.md" 2>/dev/null
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
