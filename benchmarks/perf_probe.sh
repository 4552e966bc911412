#!/usr/bin/env bash
# Issue 22's device batch: the touched tests, the post chain's dispatch shapes at 4K, the first pixel's profile,
# then the full perf suite and --explain. Results go to RESULTS (default $OUT), one tarball of folders.
#   benchmarks/perf_probe.sh [RESULTS_DIR] [--no-perf]
set -u -o pipefail
cd "$(dirname "$0")/.."
RESULTS="${1:-${OUT:-gpu-results}}"
source benchmarks/device_env.sh
export WGPURENDER_PERF_RECORD="$RESULTS/bandwidth.json"
{
    echo "date: $(date -Is)"; echo "host: $(uname -a)"; echo "cpu cores: $(nproc)"
    nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null || true
    "$PYTHON" -m wgpurender info 2>&1 || true
} > "$RESULTS/machine.txt"
"$PYTHON" -m pytest -q -p no:cacheprovider tests/test_no_poll_thread.py tests/test_frame_calls.py \
    tests/test_bandwidth_record.py tests/test_cdef_cache.py tests/test_cffi_types.py tests/test_bench.py \
    tests/test_plan_is_what_is_built.py tests/test_post_paths.py > "$RESULTS/tests.log" 2>&1
tail -3 "$RESULTS/tests.log"
"$PYTHON" -m wgpurender bench post-roofline --size 3840x2160 --frames 30 --shapes --out "$RESULTS/roofline" \
    > "$RESULTS/roofline.log" 2>&1; tail -2 "$RESULTS/roofline.log"
"$PYTHON" benchmarks/first_pixel_profile.py "$RESULTS/profile" > "$RESULTS/profile.log" 2>&1
if [ "${2:-}" != "--no-perf" ]; then
    "$PYTHON" -m wgpurender bench perf --out "$RESULTS/perf" > "$RESULTS/perf.log" 2>&1; tail -3 "$RESULTS/perf.log"
    "$PYTHON" -m wgpurender render assets/scenes/final.toml --explain --size 3840x2160 > "$RESULTS/final-explain.txt" 2>&1
    "$PYTHON" -m wgpurender render assets/scenes/final_subpass.toml --explain --size 3840x2160 \
        > "$RESULTS/final_subpass-explain.txt" 2>&1
fi
echo "done $(date -Is)"
