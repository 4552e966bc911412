"""The Python API from several threads at once: the same images as the same calls one after another (issue 28.9).

Before: ``w.render`` from several threads aborted the process (wgpu-native asserted on a device used from two
threads mid-frame) or returned another call's image (the frame loop's one readback buffer per context). The API
now holds one lock around the device's use (api.py), so concurrent calls run one at a time on the GPU.
"""

from __future__ import annotations

import subprocess
import sys

CHILD = r"""
import sys, threading
import numpy as np
import wgpurender as w

SIZE = (24, 18)
def call(k):
    kind = k % 5
    if kind == 0:
        return w.render("triangle", size=SIZE, format=("rgba8unorm-srgb", "rgba8unorm")[k // 5 % 2]).pixels
    if kind == 1:
        return w.render("3d", size=SIZE, t=(k % 7) * 0.25).pixels
    if kind == 2:
        return w.reference(("triangle", "triangle-buffers")[k // 5 % 2], size=SIZE).pixels
    if kind == 3:
        return w.render("assets/scenes/unlit.toml", size=(16 + k % 3 * 8, 12)).pixels
    a = w.render("textured", size=SIZE, t=(k % 4) * 0.5)
    b = w.reference("textured", size=SIZE, t=(k % 4) * 0.5)
    c = w.compare(a, b, flip=False)
    return np.array([c.max_abs, c.over_1], np.float64)

THREADS, CALLS = 8, 20
jobs = [[t * CALLS + i for i in range(CALLS)] for t in range(THREADS)]
expected = {k: call(k) for row in jobs for k in row}
got, errors = {}, []
def worker(row):
    try:
        for k in row:
            got[k] = call(k)
    except BaseException as err:
        errors.append(repr(err))
threads = [threading.Thread(target=worker, args=(row,)) for row in jobs]
for t in threads:
    t.start()
for t in threads:
    t.join()
assert not errors, errors
wrong = [k for k in expected if got[k].dtype != expected[k].dtype or not np.array_equal(got[k], expected[k])]
assert not wrong, f"calls {wrong} returned other images than the same calls made one after another"
assert len({expected[k].tobytes() for k in expected}) > 10  # the calls differ: a swapped image would show
print("ok", len(got))
"""


def test_eight_threads_of_mixed_calls_give_the_sequential_images(tmp_path):
    done = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=900,
                          env={**__import__("os").environ, "XDG_CACHE_HOME": str(tmp_path / "cache")})
    assert done.returncode == 0, f"exit {done.returncode}: {done.stderr[-3000:]}"  # an abort is a negative code
    assert done.stdout.split() == ["ok", "160"]
