# The GL regression's check on the GPU machine (issue 31, instance_data), from the repository root with .gl/ and
# .whl/ carried: the GL-related test files under pytest, then the probe on both backends (adapter facts, each way
# on a small scene, frame times of both ways at 10k and 100k copies). Output in $OUT/run (commands.txt, *.log).
set -u
. benchmarks/device_run_setup.sh
step pytest 110 python3 -m pytest -v -p no:cacheprovider -n 8 -o addopts="" --timeout 100 tests/test_backends.py \
  tests/test_instance_data.py tests/test_tangents.py tests/test_culling.py tests/test_instancing.py
grep -E " (FAILED|ERROR) " "$D/pytest.log" | sed 's/^\[gw[0-9]*\] //' | cut -c1-220 | sort | head -40
tail -2 "$D/pytest.log"
step probe-opengl 55 python3 benchmarks/instance_data_probe.py opengl 10000 100000
step probe-vulkan 55 python3 benchmarks/instance_data_probe.py vulkan 10000 100000
cat "$D/commands.txt"; head -12 "$D/probe-opengl.log"
