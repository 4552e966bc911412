#!/bin/sh
# Issue 31.6 on the GPU machine (post4, 2026-11-27 night: docs/perf-h100/2026-11-27-post4/). Run from a copy of the
# branch in a folder of main's checkout (the device tool carries main's tree; .gl/ and .whl/ beside, linked into
# the copy): `cd .post4 && ln -s ../.gl .gl && ln -s ../.whl .whl && sh benchmarks/post4_device_run.sh MODE`.
# - main's FXAA pass text, made by main's tree (the folder above), for the interleaved run's "fxaa main" case;
# - tests: the tiles (byte-equal to untiled), the paths, the roofline's rows, on the GPU's compute path;
# - interleave: benchmarks/post_interleave.py at 3840x2160 (every case every round, the SM clock each round);
# - MODE roofline also: `bench post-roofline --shapes=8x8x2,16x8x2` (the plan's chain in its rows).
# The SM clock (nvidia-smi -q -d CLOCK) before and after. Everything under $OUT/run, packed into $OUT/run.tgz.
set -u
MODE=${1:-probe}
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
nvidia-smi -q -d CLOCK > "$D/clock_before.txt" 2>&1
(cd .. && PYTHONPATH=$PWD:/tmp/site python3 -c "
import sys, wgpurender
from wgpurender.core.plan import resolve_plan
from wgpurender.wgpu_path.post.shaders import pass_source
print('main tree:', wgpurender.__file__.replace('$PWD', 'REPO'), file=sys.stderr)
p = resolve_plan('assets/scenes/final.toml', None, size=(3840, 2160), post_path='compute').post_passes[1]
print(pass_source(p, (8, 8, 2), False), end='')") > "$D/main_fxaa.wgsl" 2> "$D/main_fxaa.log"
step tests 120 python3 -m pytest -q -p no:cacheprovider tests/test_post_dispatch.py tests/test_post_paths.py \
  tests/test_post_roofline.py
step interleave 200 python3 benchmarks/post_interleave.py "$D/interleave" --main-wgsl "$D/main_fxaa.wgsl" \
  --rounds 30 --frames 8
if [ "$MODE" = roofline ]; then
  step roofline 150 python3 -m wgpurender bench post-roofline --size 3840x2160 --frames 50 --shapes=8x8x2,16x8x2 \
    --out "$D/roofline"
fi
nvidia-smi -q -d CLOCK > "$D/clock_after.txt" 2>&1
cat "$D/commands.txt" "$D/main_fxaa.log"; tail -3 "$D/tests.log"; grep -A40 "^| case" "$D/interleave/interleave.md"
grep "^- " "$D/interleave/interleave.md" | cut -c1-400
grep -h "^- " "$D/roofline/post-roofline-final.md" 2>/dev/null | cut -c1-300
grep -B1 -A3 "^    SM " "$D/clock_before.txt" "$D/clock_after.txt" | head -30
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
