"""Python's garbage collector and the frames that follow a load: what the load made is frozen.

A scene's load leaves tens of thousands of long-lived objects (the plan, meshes, wgpu-py wrappers); every full
collection during the frames walks them all again, and such a collection paused a frame by 4-5 ms (issue 22, the
p99 tails of issue 31.4). :func:`settle`, once a new drawable has drawn its first frame: the objects frozen after
an earlier load go back under the collector (the drawable they belonged to may be garbage now: a live reload, a
knob turned, a resize), one collection frees what is garbage, and ``gc.freeze()`` moves the survivors to the
permanent generation, which later collections skip. The collector stays on for what the frames themselves make.
Both windows call it; the benchmark's frames do the same (wgpurender/bench/frames.py, ``settle_garbage``).
"""

from __future__ import annotations

import gc


def settle() -> int:
    """Unfreeze, collect, freeze; the number of objects frozen."""
    gc.unfreeze()
    gc.collect()
    gc.freeze()
    return gc.get_freeze_count()
