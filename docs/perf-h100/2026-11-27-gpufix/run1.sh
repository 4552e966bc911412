set -u
for f in ../.gl/*.deb; do dpkg -x $f / >/dev/null 2>&1; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json XDG_RUNTIME_DIR=/tmp PYTHONUNBUFFERED=1
python3 -m pip install -q --no-index --no-deps --target /tmp/site ../.whl/*.whl > $OUT/pip.log 2>&1
export PYTHONPATH=$PWD:/tmp/site
{ date -Is; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/machine.txt 2>&1
timeout 100 python3 dump.py > $OUT/dump.log 2>&1
timeout 110 python3 -m pytest -q -p no:cacheprovider -n 8 -rfE -o addopts="" -p pytester --timeout 100 tests/test_pbr.py tests/test_ibl_scene.py tests/test_ibl.py "tests/test_exercises.py::test_solution_passes_starter_fails_and_each_mistake_is_diagnosed_as_itself" > $OUT/pytest.log 2>&1; echo "pytest rc=$?" >> $OUT/pytest.log
tail -30 $OUT/pytest.log; cat $OUT/dump.log | tail -20
