#!/usr/bin/env bash
# The whole GPU run in one script, for a machine with no package registry.
#
#   benchmarks/gpu_run.sh [RESULTS_DIR]
#
# Expects the repository as the working directory and the wheels brought along in .whl/
# (make them where PyPI is reachable: pip download --only-binary=:all: -d .whl \
#   wgpu numpy trimesh pillow vulkan flip-evaluator glfw matplotlib pytest hypothesis ... ,
# matching the target's Python). Installs them into /tmp/site without touching the system,
# then runs the full perf suite (3840x2160 included on a GPU adapter) and tests/hardcases.
# Results go to RESULTS_DIR, else $OUT, else ./gpu-results.
set -u -o pipefail

cd "$(dirname "$0")/.."
RESULTS="${1:-${OUT:-gpu-results}}"
source benchmarks/device_env.sh  # RESULTS made, wheels installed, PYTHONPATH set

{
    echo "date: $(date -Is)"
    echo "host: $(uname -a)"
    nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null || true
    "$PYTHON" -m wgpurender info 2>&1 || true
} > "$RESULTS/machine.txt"

status=0
"$PYTHON" -m wgpurender bench perf --out "$RESULTS/perf" 2>&1 | tee "$RESULTS/perf.log" || status=1
"$PYTHON" -m pytest tests/hardcases -q -p no:cacheprovider 2>&1 | tee "$RESULTS/hardcases.log" || status=1
"$PYTHON" -m wgpurender bench accuracy --out "$RESULTS/accuracy" 2>&1 | tee "$RESULTS/accuracy.log" || status=1
"$PYTHON" -m wgpurender bench accuracy --truth analytic --out "$RESULTS/accuracy_analytic" 2>&1 | tee "$RESULTS/accuracy_analytic.log" || status=1
echo "results in $RESULTS (exit $status)"
exit $status
