#!/usr/bin/env bash
# Run the numerical hard cases (tests/hardcases) and print their measured numbers on this machine's GPU.
# Usage: benchmarks/run_hardcases.sh [python]   (default: .venv/bin/python, else python3)
# On a GPU machine the first Vulkan adapter that is not a CPU is used (see wgpurender/wgpu_path/device/context.py).
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${1:-}"
if [ -z "$PY" ]; then
    if [ -x .venv/bin/python ]; then PY=.venv/bin/python; else PY=python3; fi
fi
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
"$PY" -m pytest tests/hardcases -q
"$PY" benchmarks/hardcases_report.py
