set -u
for f in ../.gl/*.deb; do dpkg -x $f / >/dev/null 2>&1; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json XDG_RUNTIME_DIR=/tmp PYTHONUNBUFFERED=1
python3 -m pip install -q --no-index --no-deps --target /tmp/site ../.whl/*.whl > /dev/null 2>&1
export PYTHONPATH=$PWD:/tmp/site
{ date -Is; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/machine.txt 2>&1
timeout 70 python3 measure2.py > $OUT/measure.log 2>&1
timeout 100 python3 -m pytest -q -p no:cacheprovider -n 12 -rfE -o addopts="" -p pytester --timeout 90 tests/test_pbr.py tests/test_ibl.py tests/test_ibl_scene.py tests/test_peak_memory.py "tests/test_exercises.py::test_solution_passes_starter_fails_and_each_mistake_is_diagnosed_as_itself[wgpu-5]" "tests/test_exercises.py::test_solution_passes_starter_fails_and_each_mistake_is_diagnosed_as_itself[raw-5]" "tests/test_exercises.py::test_solution_passes_starter_fails_and_each_mistake_is_diagnosed_as_itself[wgpu-4]" tests/test_exercises.py::test_mistakes_are_told_apart_on_an_adapter_with_wide_reference_bounds tests/test_exercises.py::test_exercise_refuses_a_symlinked_output_folder_like_every_writer tests/test_vulkan_ref_scene.py::test_scene_references_are_current tests/test_reliability_causes.py -k "not (test_reliability_causes and not 12000)" > $OUT/pytest.log 2>&1; echo "pytest rc=$?" >> $OUT/pytest.log
grep -E "FAILED|ERROR|passed|failed" $OUT/pytest.log | tail -15; cat $OUT/measure.log | tail -12
