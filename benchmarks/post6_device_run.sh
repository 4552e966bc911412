#!/bin/sh
# Issue 31.6 on the GPU machine (post6, 2026-11-27 night: docs/perf-h100/2026-11-27-post6/): FXAA's luma in the
# intermediate's alpha (wgpurender/bench/fxaa_variants/luma_alpha.py) against main's pass. Run from a copy of the branch in a folder
# of main's checkout: `cd .post6 && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/post6_device_run.sh`.
# - main's FXAA pass text, made by main's tree (the folder above), for the interleaved run's "fxaa main" case;
# - tests: the variant (byte-equal to the plan's pass, the lumas stored) and the interleave summary, on the GPU;
# - interleave: benchmarks/post_interleave.py --set gather at 3840x2160 (every case every round, the SM clock each
#   round; the chain of a gather case is "tonemap luma" + it).
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
step tests 60 python3 -m pytest -q -p no:cacheprovider tests/test_post_luma_alpha.py tests/test_post_interleave.py
step interleave 120 python3 benchmarks/post_interleave.py "$D/interleave" --main-wgsl "$D/main_fxaa.wgsl" \
  --rounds 30 --frames 8 --set gather
nvidia-smi -q -d CLOCK > "$D/clock_after.txt" 2>&1
cat "$D/commands.txt" "$D/main_fxaa.log"; tail -3 "$D/tests.log"; grep -A40 "^| case" "$D/interleave/interleave.md"
grep "^- " "$D/interleave/interleave.md" | cut -c1-400
grep -B1 -A3 "^    SM " "$D/clock_before.txt" "$D/clock_after.txt" | head -30
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
