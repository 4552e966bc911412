#!/bin/sh
# Issue 31.6 on the GPU machine (post engineer, 2026-11-27, second pass: docs/perf-h100/2026-11-27-post2/). Run from
# a copy of the branch in a folder of main's checkout (the device tool carries main's tree; .gl/ and .whl/ beside,
# linked into the copy): `cd .post && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/post_device_run.sh
# MODE`, MODE probe (first call) or final (second call).
# - tests: the dispatch shapes and FXAA's workgroup tile (tiled image byte-equal to the untiled one), the paths,
#   post_intermediate against float64 and the roofline's rows, on the GPU's compute path;
# - error: benchmarks/post_intermediate_error.py (each post_intermediate setting against float64, on the GPU);
# - probe: `bench post-roofline --shapes` at 3840x2160 (final.toml and final_subpass.toml): every variant, then
#   each fused compute pass with every dispatch shape, FXAA's pass tiled and untiled;
# - final: every variant (the chain as the plan dispatches it) and a sweep of the plan's shapes and main's
#   (32x8 x4 untiled for every pass: the baseline, same run).
# Writes everything under $OUT/run, packed into $OUT/run.tgz.
set -u
MODE=${1:-probe}
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step tests 60 python3 -m pytest -q -p no:cacheprovider tests/test_post_dispatch.py tests/test_post_paths.py \
  tests/test_post_intermediate.py tests/test_post_roofline.py
step error 25 python3 benchmarks/post_intermediate_error.py "$D/post_intermediate_error.md"
nvidia-smi --query-gpu=clocks.sm,clocks.max.sm,clocks.mem,power.draw,power.limit --format=csv >> "$D/machine.txt" 2>&1
if [ "$MODE" = probe ]; then SWEEP=--shapes; else SWEEP=--shapes=8x8x2,16x8x2,8x8x1,32x8x4; fi
step roofline 120 python3 -m wgpurender bench post-roofline --size 3840x2160 --frames 50 $SWEEP --out "$D/roofline"
cat "$D/commands.txt"; tail -3 "$D/tests.log"; grep "^| " "$D/post_intermediate_error.md" | head -13
grep -h "^- " "$D/roofline/post-roofline-final.md" "$D/roofline/post-roofline-final_subpass.md" 2>/dev/null \
  | grep -v "shape [0-9]" | cut -c1-300
grep -h "shape [0-9]" "$D/roofline/post-roofline-final.md" "$D/roofline/post-roofline-final_subpass.md" 2>/dev/null \
  | grep "^|" | cut -d"|" -f2,3,6,10 | sed 's/compute, fused//'
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"  # the tool returns at most 8 files
