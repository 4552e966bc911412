"""The raw path's stage target starts as zeros, as wgpu's textures do (raw_path/render.zero).

Found by the exercises check: a learner's step-3a starter (a 1x1 copy instead of the whole image) passed on the raw
path under pytest-xdist, because lavapipe handed the new target the memory of the previous render, which still held
the solution's image. Here a stage that forgets to write its target is rendered right after a full render.
"""

import numpy as np
import vulkan as vk

from wgpurender.raw_path.device.images import transition
from wgpurender.raw_path.render import render_reference, render_stage_class
from wgpurender.raw_path.stages.offscreen import Offscreen


class Forgetful(Offscreen):
    """The offscreen step with its copy left out: only the layouts the readback needs."""

    def record(self, cmd, target, t: float = 0.0) -> None:
        transition(cmd, target, vk.VK_IMAGE_LAYOUT_UNDEFINED, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL)
        transition(cmd, target, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)


def test_a_stage_that_writes_nothing_reads_zeros_after_a_full_render():
    size = (256, 192)  # the exercises check size: here lavapipe reuses the freed target memory
    full = render_reference("triangle", size)
    assert full.any(), "the full render must leave something in the freed memory for this test to mean anything"
    for _ in range(3):  # memory is recycled in no fixed order: several tries
        empty = render_stage_class(Forgetful, size)
        assert empty.shape == full.shape
        assert not empty.any(), f"{np.count_nonzero(empty.any(axis=2))} pixels the stage never wrote are not zero"
