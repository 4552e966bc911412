"""Course steps 1-3: the clear colours and the first triangle.

The attribute-less triangle shaders (shaders_wgsl/triangle.wgsl, shaders_glsl/triangle.vert)
hold the same numbers in their own source; the vertex-buffer stages upload these.
"""

from __future__ import annotations

import numpy as np

# Step 1a clears to zero: WebGPU's clear_texture has no colour argument, so the raw path's
# vkCmdClearColorImage clears to zero as well, for the two to be compared.
TRANSFER_CLEAR_COLOR = (0.0, 0.0, 0.0, 0.0)
# Step 1b: a colour exact in every format: values k/255 survive the float -> unorm conversion.
CLEAR_COLOR = (51 / 255, 102 / 255, 204 / 255, 1.0)

# NDC positions (x right, y up in wgpu; see docs/vulkan-mapping.md for Vulkan's y-down) and linear RGB colours.
TRIANGLE_POSITIONS = np.array([[-0.8, -0.7], [0.7, -0.5], [-0.1, 0.8]], dtype=np.float32)
TRIANGLE_COLORS = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
TRIANGLE_INDICES = np.array([0, 1, 2], dtype=np.uint16)
BACKGROUND = (0.0, 0.0, 0.0, 1.0)


def triangle_vertices() -> np.ndarray:
    """(3, 5) float32: position xy then colour rgb, the interleaved vertex buffer of step 2b."""
    return np.hstack([TRIANGLE_POSITIONS, TRIANGLE_COLORS]).astype(np.float32)

# Step 3c (msaa-post): the post effect's grey amount; fully grey is the simplest effect to check in numpy.
GREY_AMOUNT = 1.0
