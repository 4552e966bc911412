#!/bin/sh
# The evening's check on the H100 (integrator, 2026-11-27), after the play and load3 merges: the test files the
# whole-suite call at 16:14 UTC failed (concepts after play's record_copy, a stale mutation row, the same-wait
# schedule's stamp), with the playback, mesh-worker, driver-preload and animation tests (pytester loaded).
# Run from the repository root with .gl/ and .whl/ carried: `sh benchmarks/evening_check_device_run.sh`.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step tests 200 python3 -m pytest -q -p no:cacheprovider -n 15 -o addopts="" -p pytester --timeout 120 \
  tests/test_concepts_calls.py tests/test_concepts.py tests/test_mutation_rows.py tests/test_bench_perf_rows.py \
  tests/test_window_play.py tests/test_mesh_workers_ahead.py tests/test_mesh_workers.py \
  tests/test_shared_mesh_buffers.py tests/test_driver_preload.py tests/test_scene_load_scale.py \
  tests/test_gltf_animation.py tests/test_frame_caches.py tests/test_frame_calls.py
cat "$D/commands.txt"; grep -E "^(FAILED|ERROR)" "$D/tests.log" | cut -c1-200 | head -20; tail -3 "$D/tests.log"
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
