"""benchmarks/fxaa_edge_share.py's counts (issue 31.6): FXAA's edge test on a made-up image, and which warp steps
(32 invocations, one of their rows each) of an untiled dispatch hold an edge pixel, worked out by hand from the
dispatch's layout (invocation (x, y) draws rows y * rows + k; a warp is 32 consecutive local indices y * wx + x)."""

from __future__ import annotations

import numpy as np
from helpers import benchmark_script


def _module():
    return benchmark_script("fxaa_edge_share")


def test_a_lone_bright_pixel_and_its_four_neighbours_are_edges():
    rgb = np.zeros((9, 9, 3), np.float32)
    rgb[4, 4] = 1.0  # luma 1 against 0: contrast 1 > max(0.0833, 0.166 * 1)
    edge = _module().edge_mask(rgb, 0.166, 0.0833)
    assert {tuple(p) for p in np.argwhere(edge)} == {(4, 4), (3, 4), (5, 4), (4, 3), (4, 5)}
    assert not _module().edge_mask(np.full((5, 5, 3), 0.5, np.float32), 0.166, 0.0833).any()  # flat: none


def test_the_contrast_threshold_is_relative_to_the_brightest_luma():
    """Luma 0.6 around a pixel of 0.48 (grey: luminance = luma squared): contrast 0.12 is above 0.166 * 0.6 =
    0.0996 and 0.0833, so an edge, though below 0.166 itself."""
    rgb = np.full((5, 5, 3), 0.36, np.float32)
    rgb[2, 2] = 0.48 ** 2
    edge = _module().edge_mask(rgb, 0.166, 0.0833)
    assert {tuple(p) for p in np.argwhere(edge)} == {(2, 2), (1, 2), (3, 2), (2, 1), (2, 3)}


def test_warp_steps_follow_the_dispatch_layout():
    warp_steps = _module().warp_steps
    edge = np.zeros((16, 16), bool)  # 8x8 x2: 2 x 1 groups, 64 invocations (2 warps) each, 2 rows: 8 steps
    assert warp_steps(edge, (8, 8, 2)) == (0, 8)
    edge[0, 0] = True  # invocation 0, row k = 0: warp 0's first step
    assert warp_steps(edge, (8, 8, 2)) == (1, 8)
    edge[1, 0] = True  # y = 1: the same invocation's second row, another step
    edge[2, 0] = True  # y = 2: invocation y 1 (index 8), still warp 0, first step: no new step
    assert warp_steps(edge, (8, 8, 2)) == (2, 8)
    edge[8, 0] = True  # y = 8: invocation y 4, index 32: warp 1
    edge[0, 8] = True  # x = 8: the second group
    assert warp_steps(edge, (8, 8, 2)) == (4, 8)
    # 16x16 x1: one group of 256 invocations (8 warps); indices 0, 16, 8 (warp 0), 32 (warp 1), 128 (warp 4)
    assert warp_steps(edge, (16, 16, 1)) == (3, 8)
    # a partial group: 3 rows of 5 pixels in 32x8 x1, indices 0-4, 32-36, 64-68: warps 0, 1 and 2 of 8
    assert warp_steps(np.ones((3, 5), bool), (32, 8, 1)) == (3, 8)
    assert warp_steps(np.ones((4, 4), bool), (4, 4, 1)) == (1, 1)  # 16 invocations: one warp, half of it idle
