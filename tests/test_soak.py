"""The soak: many frames of the final scene at flat memory. 200 frames in ``make test``, 2,000 in ``make fuzz``.

Memory is the process's resident set (RSS, /proc/self/statm) sampled every few frames after a warm-up; a least-
squares line through the samples must rise by less than :data:`MAX_GROWTH_MB` over the whole run. A leak of one
frame's readback (the soak renders 160x120: 77 KB a frame) would add 15 MB over 200 frames.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

LONG = os.environ.get("WGPURENDER_FUZZ", "") == "long"
FRAMES = 2000 if LONG else 200
WARMUP = 20
MAX_GROWTH_MB = 8.0
FINAL = Path(__file__).resolve().parents[1] / "assets" / "scenes" / "final.toml"


def _rss_mb() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


@pytest.mark.skipif(not Path("/proc/self/statm").exists(), reason="needs Linux /proc for RSS")
def test_final_scene_soak_has_flat_memory(ctx):
    from wgpurender.wgpu_path.scene.frame import load_renderer, render_frame

    renderer = load_renderer(FINAL, ctx, size=(160, 120))
    target = renderer.create_output()
    frames, rss = [], []
    first = None
    for i in range(FRAMES):
        pixels, _ = render_frame(ctx, renderer, target, t=i / 60.0)
        if first is None:
            first = pixels
        if i >= WARMUP and i % 5 == 0:
            frames.append(i)
            rss.append(_rss_mb())
    slope = np.polyfit(frames, rss, 1)[0]  # MB per frame
    growth = slope * (FRAMES - WARMUP)
    print(f"soak: {FRAMES} frames, RSS {rss[0]:.1f} -> {rss[-1]:.1f} MB, fitted growth {growth:+.2f} MB")
    assert growth < MAX_GROWTH_MB, f"RSS grows {slope * 1024:.1f} KB per frame ({growth:.1f} MB over the run)"
    assert pixels.shape == first.shape and pixels.std() > 0  # still drawing the scene, not an empty target
