# Sourced (not run) by the issue-31 runs on the GPU machine (the device tool), from the repository root with .gl/
# and .whl/ carried: unpacks the Vulkan loader and tools, installs the wheels into /tmp/site, records the machine in
# $OUT/run/machine.txt and defines step NAME LIMIT CMD... (its command, start time and exit status in
# commands.txt, its output in NAME.log).
for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json XDG_RUNTIME_DIR=/tmp PYTHONUNBUFFERED=1
python3 -m pip install -q --no-index --no-deps --target /tmp/site .whl/*.whl && export PYTHONPATH=$PWD:/tmp/site
D=$OUT/run; mkdir -p "$D"
{ date -u; nvidia-smi -L; nvidia-smi --query-gpu=driver_version --format=csv,noheader; lscpu | grep "Model name";
  nproc; python3 --version; } > "$D/machine.txt" 2>&1
step() { name=$1; limit=$2; shift 2; echo "== $name: $*" >> "$D/commands.txt"; date -u +%H:%M:%S >> "$D/commands.txt"
         timeout "$limit" "$@" > "$D/$name.log" 2>&1; echo "rc $?" >> "$D/commands.txt"; }
