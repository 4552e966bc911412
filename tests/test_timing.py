"""Timestamps measure real GPU work: a pass that draws more takes longer than an empty one."""

from __future__ import annotations

import pytest

from wgpurender.wgpu_path.device.targets import create_target
from wgpurender.wgpu_path.device.timing import PassTimer, Stats, wall_time
from wgpurender.wgpu_path.stages import get_stage


def test_stats_of_known_samples():
    s = Stats.of([5.0, 1.0, 3.0, 2.0, 4.0])
    assert (s.median, s.n) == (3.0, 5)
    assert s.p10 == pytest.approx(1.4) and s.p90 == pytest.approx(4.6)


def test_wall_time_runs_warmup_then_repeats():
    calls = []
    stats = wall_time(lambda: calls.append(1), warmup=3, repeats=7)
    assert len(calls) == 10 and stats.n == 7


def test_pass_timestamps_order_work(ctx):
    """Timing two passes in one frame: a 4x MSAA 512x512 triangle costs more GPU time than an empty clear."""
    if not ctx.has("timestamp-query"):
        pytest.skip("adapter has no timestamp-query")
    timer = PassTimer(ctx)
    target = create_target(ctx, (512, 512), "rgba8unorm")
    tri = get_stage("msaa")(ctx, "rgba8unorm")
    tri.resize((512, 512))
    results = []
    for _ in range(5):
        timer.reset()
        encoder = ctx.device.create_command_encoder()
        empty = encoder.begin_render_pass(
            color_attachments=[{"view": target.create_view(), "load_op": "clear", "store_op": "store",
                                "clear_value": (0, 0, 0, 1)}],
            timestamp_writes=timer.writes("empty"),
        )
        empty.end()
        rp = encoder.begin_render_pass(color_attachments=[tri.color_attachment(target)],
                                       timestamp_writes=timer.writes("triangle"))
        rp.set_pipeline(tri.pipeline)
        rp.draw(3)
        rp.end()
        timer.resolve(encoder)
        ctx.queue.submit([encoder.finish()])
        results.append(timer.read())
    last = results[-1]
    assert set(last) == {"empty", "triangle"}
    assert all(v >= 0 for v in last.values())
    # The fastest of 5 frames per pass: on a loaded machine (lavapipe runs on the CPU) one frame's pass can be
    # preempted; the minimum is the pass's own cost.
    fastest = {label: min(r[label] for r in results[1:]) for label in last}
    assert fastest["triangle"] > fastest["empty"], fastest


def test_deferred_timer_keeps_each_frames_passes_apart(ctx):
    """frames > 1: every frame resolves into its own slot; collect() returns them in order, then nothing.

    Frame 0 times one empty pass; frames 1-5 an empty pass and a 4x MSAA 512x512 triangle. A slot
    offset gone wrong mixes the frames' labels or reads another slot's ticks (the triangle's time
    would not exceed the empty pass's; the fastest of 5 frames, as a loaded machine can preempt one).
    """
    if not ctx.has("timestamp-query"):
        pytest.skip("adapter has no timestamp-query")
    timer = PassTimer(ctx, frames=6)
    target = create_target(ctx, (512, 512), "rgba8unorm")
    tri = get_stage("msaa")(ctx, "rgba8unorm")
    tri.resize((512, 512))
    for k in range(6):
        timer.reset()
        encoder = ctx.device.create_command_encoder()
        empty = encoder.begin_render_pass(
            color_attachments=[{"view": target.create_view(), "load_op": "clear", "store_op": "store",
                                "clear_value": (0, 0, 0, 1)}],
            timestamp_writes=timer.writes("empty"),
        )
        empty.end()
        if k:
            rp = encoder.begin_render_pass(color_attachments=[tri.color_attachment(target)],
                                           timestamp_writes=timer.writes("triangle"))
            rp.set_pipeline(tri.pipeline)
            rp.draw(3)
            rp.end()
        timer.resolve(encoder)
        ctx.queue.submit([encoder.finish()])
        assert timer.read() == {}  # deferred: nothing per frame
    frames = timer.collect()
    assert [sorted(f) for f in frames] == [["empty"]] + [["empty", "triangle"]] * 5
    assert all(v >= 0 for f in frames for v in f.values())
    fastest = {label: min(f[label] for f in frames[1:]) for label in ("empty", "triangle")}
    assert fastest["triangle"] > fastest["empty"], fastest
    assert timer.collect() == []
