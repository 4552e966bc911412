"""The image-based lighting maps' buffer regions: one rule in the core (ibl_maps.regions, packed_regions), used by
both paths. A storage binding's offset must be a multiple of the device's minStorageBufferOffsetAlignment (at most
256 on any device); before, only the raw path stated it, and the wgpu path relied on today's sizes being multiples
of 16 texels. Here sizes that break it are made at run time: both paths refuse them with the core's one message
before any GPU call, instead of a validation error (wgpu) or a bare assert (raw)."""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.core.course import ibl_maps

ODD = (33, 15)  # 495 texels: 7920 bytes, not a multiple of 256


def test_regions_start_at_multiples_of_256_and_pad_only_what_needs_it():
    passes = [("a", (33, 15), 1), ("b", (16, 16), 2), ("c", (1, 1), 1)]
    offsets, size = ibl_maps.regions(passes)
    first = 16 * 33 * 15  # 7920 -> the next multiple of 256: 31 x 256 = 7936
    assert offsets == [0, 7936, 7936 + 16 * 16 * 16 * 2]
    assert size == offsets[2] + 256  # one texel still takes a whole region
    assert ibl_maps.regions([("a", (16, 16), 1)]) == ([0], 16 * 16 * 16)  # aligned already: no padding
    assert 7936 - first == 16 and all(o % 256 == 0 for o in offsets)


def test_the_scene_sizes_pack_back_to_back_at_aligned_offsets():
    (iw, ih), (pw, ph), levels = ibl_maps.IRRADIANCE_SIZE, ibl_maps.PREFILTER_SIZE, ibl_maps.LEVELS
    assert ibl_maps.packed_regions() == [0, 16 * iw * ih, 16 * (iw * ih + levels * pw * ph)]


def _odd_sizes(monkeypatch):
    monkeypatch.setattr(ibl_maps, "IRRADIANCE_SIZE", ODD)


def _refused(call):
    with pytest.raises(ValueError) as err:
        call()
    message = str(err.value)
    assert "\n" not in message and "multiples of 256 bytes" in message and "irradiance 33x15x1" in message


def test_the_wgpu_path_refuses_unaligned_regions_before_the_gpu(monkeypatch):
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene.ibl import scene_maps_buffer

    _odd_sizes(monkeypatch)
    _refused(lambda: scene_maps_buffer(get_context(), np.ones((8, 16, 3)), 16))


def test_the_raw_path_refuses_unaligned_regions_with_the_same_rule(monkeypatch):
    from contextlib import ExitStack

    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.scene.ibl import scene_maps_buffer

    _odd_sizes(monkeypatch)
    with ExitStack() as owned:
        _refused(lambda: scene_maps_buffer(get_vulkan(), owned, np.ones((8, 16, 3)), 16))


def test_the_raw_readback_pads_unaligned_sizes_and_matches_the_wgpu_maps():
    """make_maps at sizes that need padding: each region bound at its aligned offset reads back the same maps
    as the wgpu path's separate buffers (a wrong offset would mix or lose texels)."""
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.scene.ibl import make_maps as raw_maps
    from wgpurender.wgpu_path.device.context import get_context
    from wgpurender.wgpu_path.scene.ibl import make_maps as wgpu_maps

    sky = np.random.default_rng(3).uniform(0.1, 2.0, (8, 16, 3))
    sizes = {"levels": 2, "irradiance_size": ODD, "prefilter_size": (9, 5), "lut_size": 5}
    raw, wgpu = raw_maps(get_vulkan(), sky, 16, **sizes), wgpu_maps(get_context(), sky, 16, **sizes)
    for a, b in ((raw.irradiance, wgpu.irradiance), (raw.prefiltered, wgpu.prefiltered), (raw.lut, wgpu.lut)):
        assert a.shape == b.shape
        np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-6)
