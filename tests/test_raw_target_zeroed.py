"""The raw path's stage target starts as zeros, as wgpu's textures do (raw_path/render.zero), by the Vulkan spec: the
stages' barriers on it start from TARGET_LAYOUT, never from UNDEFINED (which lets a driver discard the zeros).

Found by the exercises check: a learner's step-3a starter (a 1x1 copy instead of the whole image) passed on the raw
path under pytest-xdist, because lavapipe handed the new target the memory of the previous render, which still held
the solution's image. Here a stage that forgets to write its target is rendered right after a full render.
"""

import numpy as np
import pytest
import vulkan as vk

from wgpurender.raw_path import render as raw_render
from wgpurender.raw_path.device.images import transition
from wgpurender.raw_path.render import render_reference, render_stage_class
from wgpurender.raw_path.stages import all_ref_stages
from wgpurender.raw_path.stages.base import TARGET_LAYOUT
from wgpurender.raw_path.stages.offscreen import Offscreen


class Forgetful(Offscreen):
    """The offscreen step with its copy left out: only the layouts the readback needs."""

    def record(self, cmd, target, t: float = 0.0) -> None:
        transition(cmd, target, TARGET_LAYOUT, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL)
        transition(cmd, target, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)


def test_a_stage_that_writes_nothing_reads_zeros_after_a_full_render():
    size = (256, 192)  # the exercises check size: here lavapipe reuses the freed target memory
    full = render_reference("triangle", size)
    assert full.any(), "the full render must leave something in the freed memory for this test to mean anything"
    for _ in range(3):  # memory is recycled in no fixed order: several tries
        empty = render_stage_class(Forgetful, size)
        assert empty.shape == full.shape
        assert not empty.any(), f"{np.count_nonzero(empty.any(axis=2))} pixels the stage never wrote are not zero"


@pytest.mark.parametrize("name", sorted(all_ref_stages()))
def test_no_barrier_on_the_target_discards_its_zeros(monkeypatch, name):
    """Every barrier recorded on the target, from the clear that zeroes it to the readback: the first is the
    clear's (UNDEFINED -> TARGET_LAYOUT), and no later one starts from UNDEFINED, whose contents the spec lets a
    driver discard (lavapipe keeps them, so the pixels alone cannot tell). The offscreen and clear stages started
    their transfers from UNDEFINED before."""
    made, layouts = [], []
    create_image = raw_render.create_image

    def target(*args, **kwargs):
        made.append(create_image(*args, **kwargs))
        return made[-1]

    barrier = vk.vkCmdPipelineBarrier

    def spy(cmd, src, dst, flags, n_memory, memory, n_buffer, buffers, n_image, images):
        layouts.extend((b.oldLayout, b.newLayout) for b in (images or []) if made and b.image == made[0].handle)
        return barrier(cmd, src, dst, flags, n_memory, memory, n_buffer, buffers, n_image, images)

    monkeypatch.setattr(raw_render, "create_image", target)
    monkeypatch.setattr(vk, "vkCmdPipelineBarrier", spy)
    render_stage_class(all_ref_stages()[name], (32, 24))
    assert layouts[0] == (vk.VK_IMAGE_LAYOUT_UNDEFINED, TARGET_LAYOUT)
    assert all(old != vk.VK_IMAGE_LAYOUT_UNDEFINED for old, _ in layouts[1:]), layouts
