#!/bin/sh
# Issue 31's second run on the GPU machine (perf2, items 6, 4 and 8): the post chain against a copy of its bytes
# at 4K, the final scene's CPU per frame, and bench perf on the Dawn binding beside wgpu-native (same flags).
# Run from the repository root with .gl/ and .whl/ carried. Writes everything under $OUT/run.
set -u
for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json XDG_RUNTIME_DIR=/tmp PYTHONUNBUFFERED=1
python3 -m pip install -q --no-index --no-deps --target /tmp/site .whl/*.whl && export PYTHONPATH=$PWD:/tmp/site
D=$OUT/run; mkdir -p "$D"
{ date -u; nvidia-smi -L; nvidia-smi --query-gpu=driver_version --format=csv,noheader; lscpu | grep "Model name";
  nproc; python3 --version; } > "$D/machine.txt" 2>&1
step() { name=$1; limit=$2; shift 2; echo "== $name: $*" >> "$D/commands.txt"; date -u +%H:%M:%S >> "$D/commands.txt"
         timeout "$limit" "$@" > "$D/$name.log" 2>&1; echo "rc $?" >> "$D/commands.txt"; }
step roofline 90 python3 -m wgpurender bench post-roofline --size 3840x2160 --frames 50 --out "$D/roofline"
step scene 100 python3 -m wgpurender bench perf --only scene --out "$D/scene"
step dawn 100 env WGPURENDER_BINDING=dawn python3 -m wgpurender bench perf --only frames,scene --no-raw --no-big \
  --out "$D/dawn"
step native 80 python3 -m wgpurender bench perf --only frames,scene --no-raw --no-big --out "$D/native"
tar czf "$OUT/run.tgz" -C "$OUT" run
