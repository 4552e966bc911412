"""The base image size ``bench accuracy`` times at, per adapter type: the one home of that choice.

A software rasteriser (lavapipe, adapter type "CPU") spends milliseconds on a 160x120 frame, so small sizes keep
a run short and its timings still differ between settings. A hardware GPU finishes such a frame in the time it
takes to submit it: every setting read 0.1 ms at 160x120 on an H100, which says nothing about the settings.
There the base size is as large as the ground truth allows: it renders 8x the base size, and WebGPU's default
``max-texture-dimension-2d`` is 8192, so 1024 pixels wide at most. The committed H200 run
(docs/perf-h200/accuracy.csv) shows the GPU time growing with the pixels there: MSAA 4 at 400x300 0.30 ms, its 8x
ground truth (64x the pixels) 17.3 ms; so 960x720 puts the final scene's settings near 1-2 ms, well above the
empty frame (bench/accuracy_floor.py). Not yet measured on a GPU at these sizes.
"""

from __future__ import annotations

PRESETS = ("quick", "full")
SOFTWARE = {"quick": (160, 120), "full": (400, 300)}  # adapter type "CPU"
HARDWARE = {"quick": (960, 720), "full": (1024, 768)}  # every other adapter type (discrete, integrated, virtual)


def accuracy_size(adapter_type: str, preset: str) -> tuple[int, int]:
    """The base size of ``bench accuracy`` (``preset`` "quick" or "full") on an adapter of ``adapter_type``."""
    if preset not in PRESETS:
        raise ValueError(f"preset {preset!r}: choose one of {PRESETS}")
    return (SOFTWARE if adapter_type == "CPU" else HARDWARE)[preset]
