#!/bin/sh
# The late session's closing H100 calls for issue 31 (integrator, 2026-11-27), on main with load7, bench7 and the
# translate-only transform merged. MODE scale: bench perf's scene-scale (1k, 10k: instanced, batched, distinct,
# pygfx) and control families; benchmarks/batched_gpu_probe.py (why batched/N's GPU time read 5.7x instanced/N's
# in bench7's call); benchmarks/load_compare.py of this tree against the night's (6534ca3, carried in .lateold:
# `git archive 6534ca3 wgpurender assets/textures shaders_wgsl | tar -x -C .lateold`), batched and distinct 10k, cold and warm, alternating.
# MODE final: each scene-scale scene alone in a fresh process, in two orders (batched_gpu_probe.py --alone: the
# scale call read the three alike interleaved, bench perf's rows did not), then bench perf's scene-scale (with
# bench8's paired pygfx rounds) and control families, and its frames, scene and control families (the p99 rows
# beside the host's own control). MODE tests: the whole suite (as .gl/run_pytest.sh: pytester loaded, the wheel
# and fuzz tests left out).
# Each mode is one call (at most 10 minutes). Run from the repository root with .gl/ and .whl/ (and .lateold/)
# carried: `sh benchmarks/late_device_run.sh MODE`. Writes $OUT/run.tgz.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
if [ "${1:-}" = scale ]; then
  step scale 150 python3 -m wgpurender bench perf --only scene-scale,control --counts 1000,10000 --out "$D/perf-scale"
  step probe 120 python3 benchmarks/batched_gpu_probe.py "$D/batched_gpu_probe.csv" 1000,10000
  for r in 1 2; do
    for scene in batched distinct; do
      for cache in cold warm; do
        step "late_${scene}_${cache}_$r" 40 python3 benchmarks/load_compare.py late 10000 "$D/load_compare.csv" \
          "$cache" --scene="$scene"
        step "night_${scene}_${cache}_$r" 40 env PYTHONPATH="$PWD/.lateold:/tmp/site" python3 \
          benchmarks/load_compare.py night 10000 "$D/load_compare.csv" "$cache" --scene="$scene"
      done
    done
  done
  for f in "$D"/late_*.log "$D"/night_*.log; do echo "## $(basename "$f")"; tail -3 "$f"; done > "$D/load_logs.txt" 2>&1
  rm -f "$D"/late_*.log "$D"/night_*.log
  cat "$D/commands.txt"; sed -n '/^## Targets/,/^## Tails/p' "$D/perf-scale/report.md" 2>/dev/null
  cat "$D/batched_gpu_probe.csv" "$D/load_compare.csv"
elif [ "${1:-}" = final ]; then
  for order in "instanced batched distinct" "distinct batched instanced"; do
    for n in 1000 10000; do
      for scene in $order; do
        step "alone_${scene}_$n" 40 python3 benchmarks/batched_gpu_probe.py --alone "$scene" "$n" "$D/alone.csv"
      done
    done
  done
  rm -f "$D"/alone_*.log; cat "$D/alone.csv"
  step scale 150 python3 -m wgpurender bench perf --only scene-scale,control --counts 1000,10000 --out "$D/perf-scale"
  step frames 200 python3 -m wgpurender bench perf --only frames,scene,control --out "$D/perf-frames"
  cat "$D/commands.txt"; sed -n '/^## Targets/,/^## Tails/p' "$D/perf-scale/report.md" "$D/perf-frames/report.md"
else
  step tests 420 python3 -m pytest -q -p no:cacheprovider -n 15 -o addopts="" -p pytester --timeout 120 \
    --ignore tests/test_wheel.py --ignore tests/fuzz
  cat "$D/commands.txt"; grep -E "^(FAILED|ERROR)" "$D/tests.log" | cut -c1-200 | head -30; tail -3 "$D/tests.log"
fi
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
