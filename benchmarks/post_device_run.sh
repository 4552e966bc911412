#!/bin/sh
# Issue 31.4 and 31.6 on the GPU machine (post engineer, 2026-11-27). Run from a copy of the branch in a folder of
# main's checkout (the device tool carries main's tree; .gl/ and .whl/ beside, linked into the copy):
# `cd .post && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/post_device_run.sh`.
# - error: benchmarks/post_intermediate_error.py (each post_intermediate setting against float64, on the GPU);
# - tests: the storage twin (byte-equal to the scratch-and-copy path) and post_intermediate against float64, on
#   the GPU's compute path;
# - roofline: `bench post-roofline` at 3840x2160 (final.toml and final_subpass.toml), every variant with
#   post_intermediate auto, rgba8unorm, rgba8unorm-srgb and none, and the fused compute passes' dispatch shapes
#   (auto and none);
# - scene_post, scene_main: `bench perf --only scene --no-raw` of this branch, then of main's tree (the folder
#   above), same machine: the final scene's CPU per frame with and without the output copy.
# Writes everything under $OUT/run.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
MAIN=$(cd .. && pwd)
step tests 40 python3 -m pytest -q -p no:cacheprovider tests/test_post_paths.py tests/test_post_intermediate.py \
  tests/test_plan.py tests/test_post_roofline.py
step error 25 python3 benchmarks/post_intermediate_error.py "$D/post_intermediate_error.md"
step roofline 90 python3 -m wgpurender bench post-roofline --size 3840x2160 --frames 50 --shapes --out "$D/roofline"
step scene_post 45 python3 -m wgpurender bench perf --only scene --no-raw --out "$D/scene_post"
step scene_main 45 env PYTHONPATH="$MAIN:/tmp/site" sh -c "cd '$MAIN' && python3 -m wgpurender bench perf \
  --only scene --no-raw --out '$D/scene_main'"
cat "$D/commands.txt"; tail -3 "$D/tests.log"; grep "^| " "$D/post_intermediate_error.md" | head -13
grep -h "^- " "$D/roofline/post-roofline-final.md" "$D/roofline/post-roofline-final_subpass.md" 2>/dev/null \
  | grep -v shape | cut -c1-250
grep -h "final,wgpu,.*cpu_ms:untimed" "$D/scene_post/results.csv" "$D/scene_main/results.csv" 2>/dev/null | cut -c1-90
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"  # the tool returns at most 8 files
