#!/bin/sh
# Issue 31.6 on the GPU machine (post5, 2026-11-27 night: docs/perf-h100/2026-11-27-post5/): FXAA over an edge
# list (wgpurender/bench/fxaa_variants/edge_list.py) against main's one-dispatch pass. Run from a copy of the branch in a folder of
# main's checkout: `cd .post5 && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/post5_device_run.sh [all|interleave]`.
# - main's FXAA pass text, made by main's tree (the folder above), for the interleaved run's "fxaa main" case;
# - tests (mode all, the default): the edge list (byte-equal to one dispatch, the listed count) and the dispatch/tile tests, on the GPU;
# - interleave: benchmarks/post_interleave.py at 3840x2160 (every case every round, the SM clock each round).
# The SM clock (nvidia-smi -q -d CLOCK) before and after. Everything under $OUT/run, packed into $OUT/run.tgz.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
nvidia-smi -q -d CLOCK > "$D/clock_before.txt" 2>&1
(cd .. && PYTHONPATH=$PWD:/tmp/site python3 -c "
import sys, wgpurender
from wgpurender.core.plan import resolve_plan
from wgpurender.wgpu_path.post.shaders import pass_source
print('main tree:', wgpurender.__file__.replace('$PWD', 'REPO'), file=sys.stderr)
p = resolve_plan('assets/scenes/final.toml', None, size=(3840, 2160), post_path='compute').post_passes[1]
print(pass_source(p, (8, 8, 2), ''), end='')") > "$D/main_fxaa.wgsl" 2> "$D/main_fxaa.log"
[ "${1:-all}" = all ] && step tests 100 python3 -m pytest -q -p no:cacheprovider tests/test_post_edge_list.py tests/test_post_dispatch.py
step interleave 150 python3 benchmarks/post_interleave.py "$D/interleave" --main-wgsl "$D/main_fxaa.wgsl" \
  --rounds 30 --frames 8
nvidia-smi -q -d CLOCK > "$D/clock_after.txt" 2>&1
cat "$D/commands.txt" "$D/main_fxaa.log"; tail -3 "$D/tests.log"; grep -A40 "^| case" "$D/interleave/interleave.md"
grep "^- " "$D/interleave/interleave.md" | cut -c1-400
grep -B1 -A3 "^    SM " "$D/clock_before.txt" "$D/clock_after.txt" | head -30
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
