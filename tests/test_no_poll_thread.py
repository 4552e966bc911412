"""Every readback waits on the caller's thread: wgpu-py's poll thread is never woken (issue 22.1).

wgpu-py 0.32 wakes its per-device ``PollThread`` through ``get_token()`` (every ``map_async``,
``on_submitted_work_done``...). Two threads waiting for one map cost ~5-10 ms stalls on NVIDIA; the
check here needs no timing: it counts the tokens the real thread hands out while each readback path
runs, and a plain ``map_sync`` shows that the count does see a wake.
"""

from __future__ import annotations

import numpy as np
import pytest
import wgpu

from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.device.targets import create_target, read_texture
from wgpurender.wgpu_path.device.timing import PassTimer

RED = (1.0, 0.0, 0.0, 1.0)


@pytest.fixture
def wakes(ctx, monkeypatch):
    """A list that grows by one each time something asks the device's poll thread for a token."""
    poller = ctx.device._poller
    seen: list[int] = []
    real = poller.get_token

    def counting():
        seen.append(1)
        return real()

    monkeypatch.setattr(poller, "get_token", counting)
    return seen


def _clear(color):
    def record(encoder, target, t):
        encoder.begin_render_pass(color_attachments=[{
            "view": target.create_view(), "load_op": "clear", "store_op": "store", "clear_value": color}]).end()
    return record


def test_the_count_sees_a_plain_map_sync(ctx, wakes):
    buf = ctx.device.create_buffer(size=16, usage=wgpu.BufferUsage.MAP_READ | wgpu.BufferUsage.COPY_DST)
    buf.map_sync(wgpu.MapMode.READ)
    buf.unmap()
    assert wakes  # wgpu-py's own map wakes the thread: the instrument works


def test_read_texture_wakes_no_thread(ctx, wakes):
    target = create_target(ctx, (40, 30), "rgba8unorm")
    run_frame(ctx, _clear(RED), target, read_back=False, wait=True)
    pixels = read_texture(ctx, target)
    assert pixels.shape == (30, 40, 4) and (pixels == [255, 0, 0, 255]).all()
    assert wakes == []


def test_frame_readback_and_timestamps_wake_no_thread(ctx, wakes):
    """The frame loop's readback, a per-frame timestamp read and a deferred collect, several frames."""
    target = create_target(ctx, (33, 17), "rgba8unorm")
    timer = PassTimer(ctx)
    deferred = PassTimer(ctx, frames=4)
    for i in range(4):
        color = (0.0, i / 4, 0.0, 1.0)
        frame = run_frame(ctx, _timed_clear(timer, color), target, timer=timer)
        assert (abs(frame.pixels[..., 1].astype(int) - i / 4 * 255) <= 1).all()  # NVIDIA 63, llvmpipe 64
        assert set(frame.gpu_ms) == ({"clear"} if ctx.has("timestamp-query") else set())
        run_frame(ctx, _timed_clear(deferred, RED), target, read_back=False, timer=deferred)
    if ctx.has("timestamp-query"):
        assert len(deferred.collect()) == 4
    ctx.wait_idle()
    assert wakes == []


def _timed_clear(timer, color):
    def record(encoder, target, t):
        encoder.begin_render_pass(color_attachments=[{
            "view": target.create_view(), "load_op": "clear", "store_op": "store", "clear_value": color}],
            timestamp_writes=timer.writes("clear")).end()
    return record


def test_read_buffer_wakes_no_thread(ctx, wakes):
    words = np.arange(7, dtype=np.uint32) * 3 + 1
    src = ctx.device.create_buffer_with_data(data=words.tobytes(), usage=wgpu.BufferUsage.COPY_SRC)
    got = np.frombuffer(ctx.read_buffer(src, 4, 20), dtype=np.uint32)
    np.testing.assert_array_equal(got, words[1:6])
    assert wakes == []


def test_the_poll_thread_is_restored_after_a_readback(ctx):
    """The stand-in poller lives for one map_async only: after a readback the device's own poller is back, so
    wgpu-py's own maps (and anything else asking it for a token) still wake the thread."""
    poller = ctx.device._poller
    src = ctx.device.create_buffer_with_data(data=bytes(range(16)), usage=wgpu.BufferUsage.COPY_SRC)
    assert ctx.read_buffer(src, 8) == bytes(range(8, 16))
    assert ctx.device._poller is poller
