#!/usr/bin/env bash
# The reference-tolerance run for a GPU (issue 12): one command, results in one folder.
#
#   benchmarks/verify_run.sh [RESULTS_DIR]
#
# Installs the wheels in .whl/ like benchmarks/gpu_run.sh (or uses the current Python), then:
#   1. wgpurender verify --out RESULTS/verify: the matrix (verify.csv, verify.md, heatmaps/) and
#      RESULTS/verify/tolerances.toml, the table with this driver class's rows calibrated from this run;
#   2. the whole test suite with the committed table (RESULTS/pytest.log): no reference test may skip;
#   2b. wgpurender verify --implementations all --out RESULTS/implementations: the pairwise matrix
#      (implementations.md for docs/verification.md's NVIDIA section);
#   3. the reference tests again with the calibrated table (RESULTS/pytest-calibrated.log), in this
#      copy only. Failed image comparisons leave RESULTS/test-diffs/.
# Bring back RESULTS (all of it); adopt the calibration with
#   cp RESULTS/verify/tolerances.toml assets/reference/tolerances.toml
set -u -o pipefail

cd "$(dirname "$0")/.."
RESULTS="$(realpath -m "${1:-${OUT:-verify-results}}")"
source benchmarks/device_env.sh  # RESULTS made, wheels installed, PYTHONPATH set

{
    echo "date: $(date -Is)"
    echo "host: $(uname -a)"
    grep -m1 "model name" /proc/cpuinfo || true
    nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null || true
    "$PYTHON" -m wgpurender info 2>&1 || true
} > "$RESULTS/machine.txt"

status=0
"$PYTHON" -m wgpurender verify --out "$RESULTS/verify" 2>&1 | tee "$RESULTS/verify.log" || status=1
# The implementation matrix (docs/verification.md): raw and wgpu-vulkan, and wgpu-gl where the driver offers EGL;
# the wgpu-gl bounds were calibrated on lavapipe, so on a GPU those pairs are reported (info), not bounded.
"$PYTHON" -m wgpurender verify --implementations all --out "$RESULTS/implementations" 2>&1 \
    | tee "$RESULTS/implementations.log" || status=1
"$PYTHON" -m pytest -q -p no:cacheprovider -rfEs 2>&1 | tee "$RESULTS/pytest.log" | tail -15 || status=1
[ -d out/test-diffs ] && cp -r out/test-diffs "$RESULTS/test-diffs" && rm -rf out/test-diffs
if [ -f "$RESULTS/verify/tolerances.toml" ]; then
    cp "$RESULTS/verify/tolerances.toml" assets/reference/tolerances.toml
    "$PYTHON" -m pytest -q -p no:cacheprovider -rfEs tests/test_vulkan_ref.py tests/test_vulkan_ref_scene.py \
        tests/test_vulkan_tutorial.py tests/test_reference_tolerances.py tests/test_verify.py 2>&1 \
        | tee "$RESULTS/pytest-calibrated.log" | tail -15 || status=1
    [ -d out/test-diffs ] && cp -r out/test-diffs "$RESULTS/test-diffs-calibrated"
fi
echo "results in $RESULTS (exit $status)"
exit $status
