set -u
for f in .gl/*.deb; do dpkg -x $f / >/dev/null 2>&1; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json XDG_RUNTIME_DIR=/tmp PYTHONUNBUFFERED=1
python3 -m pip install -q --no-index --no-deps --target /tmp/site .whl/*.whl > $OUT/pip.log 2>&1
export PYTHONPATH=$PWD:/tmp/site
timeout 300 python3 -m pytest -v -p no:cacheprovider -n 15 -o addopts="" -p pytester --timeout 120 --ignore tests/test_wheel.py --ignore tests/fuzz > $OUT/pytest.log 2>&1; echo "pytest rc=$?" >> $OUT/pytest.log
grep -E " (FAILED|ERROR) " $OUT/pytest.log | sed 's/^\[gw[0-9]*\] //' | cut -c1-200 | sort | head -80
grep -cE " PASSED " $OUT/pytest.log; grep -cE " SKIPPED " $OUT/pytest.log; tail -2 $OUT/pytest.log
