#!/bin/sh
# bench7's H100 call for issue 31 (2026-11-27, late): bench perf's scene-scale family at 1k and 10k (instanced,
# batched: N [[models]] of one mesh file, distinct; pygfx beside where installed) and the control family (a fixed
# CPU workload and an empty GPU round trip, sampled as the frame rows are: the host's own p99). One call, at most
# 4 minutes. Run from the repository root with .gl/ and .whl/ carried: `sh benchmarks/bench7_device_run.sh`.
# Writes $OUT/run.tgz.
set -u
. benchmarks/device_run_setup.sh  # loader, wheels, machine.txt, step()
step perf 170 python3 -m wgpurender bench perf --only scene-scale,control --counts 1000,10000 --out "$D/perf"
cat "$D/commands.txt"; sed -n '/^## Targets/,/^## Tails/p' "$D/perf/report.md" 2>/dev/null
sed -n '/^## Scene scale/,$p' "$D/perf/report.md" 2>/dev/null | cut -c1-220 | head -40
tail -5 "$D/perf.log"
tar czf "$OUT/run.tgz" -C "$OUT" run && rm -rf "$OUT/run"
