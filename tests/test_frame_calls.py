"""The final scene's steady-state frame costs a handful of native calls (issue 22.2), on both post paths.

Counted by wrapping the device, queue and encoders (wgpurender/bench/calls.py), not by timing: the static
draws replay from render bundles, bind groups and views are made once, the camera is uploaded only when it
changes, and a steady frame creates nothing. The pinned numbers are the ones reached (a regression
shows as a larger count; a smaller one should lower the pin).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wgpurender.bench.calls import count_frame, steady_calls
from wgpurender.wgpu_path.scene import load_renderer

FINAL = Path(__file__).resolve().parent.parent / "assets" / "scenes" / "final.toml"
# encoder 1 + scene pass (begin, execute_bundles, end) 3 + finish 1 + submit 1, then the post chain:
# fragment: 2 passes of 3 (begin, execute_bundles, end); compute: one compute pass (begin, end) and per
# dispatch 3 (set_pipeline, set_bind_group, dispatch), plus the copy into the -srgb output.
PINNED = {"fragment": 6 + 2 * 3, "compute": 6 + 2 + 2 * 3 + 1}


@pytest.mark.parametrize("post_path", ["fragment", "compute"])
def test_final_scene_frame_calls_are_pinned(ctx, post_path):
    renderer = load_renderer(FINAL, ctx, size=(96, 72), knobs={"post_path": post_path})
    target = renderer.create_output()
    first = count_frame(ctx, renderer.record, target)
    calls = steady_calls(ctx, renderer.record, target)
    assert sum(calls.values()) <= PINNED[post_path], dict(calls)
    assert not any(k.startswith("device.create_") and k != "device.create_command_encoder" for k in calls), calls
    assert "queue.write_buffer" not in calls  # the camera was uploaded once, in the first frame
    assert first["queue.write_buffer"] >= 1
    assert calls["render_pass.execute_bundles"] == (3 if post_path == "fragment" else 1)


def test_bundles_are_recorded_once_and_survive_a_resize(ctx, monkeypatch):
    """The scene pass's bundle is made at set-up and kept across a resize (it needs formats, not textures)."""
    renderer = load_renderer(FINAL, ctx, size=(96, 72), knobs={"post_path": "compute"})
    bundle = renderer.scene_pass.bundle
    made = []
    real = ctx.device.create_render_bundle_encoder
    monkeypatch.setattr(ctx.device, "create_render_bundle_encoder", lambda **kw: made.append(kw) or real(**kw))
    for size in ((96, 72), (64, 48), (96, 72)):
        target = renderer.create_output() if size == (96, 72) else _output(ctx, renderer, size)
        count_frame(ctx, renderer.record, target)
    assert renderer.scene_pass.bundle is bundle and made == []


def _output(ctx, renderer, size):
    from wgpurender.wgpu_path.device.targets import TARGET_USAGE, create_target

    return create_target(ctx, size, renderer.plan.target_format, usage=TARGET_USAGE | renderer.target_usage)


def test_dispatches_sharing_one_compute_pass_give_the_bytes_of_separate_passes(ctx):
    """The untimed frame records the compute post chain as ONE compute pass with a dispatch per planned pass; the
    timed frame (a PassTimer: each planned pass its own compute pass, for its timestamps) keeps them apart. WebGPU
    makes each dispatch its own usage scope, so the second dispatch reads what the first wrote either way: the
    bytes are equal (on lavapipe, with validation on: tests/conftest.py fails on a validation error)."""
    from wgpurender.wgpu_path.device.frame_loop import run_frame
    from wgpurender.wgpu_path.device.timing import PassTimer

    renderer = load_renderer(FINAL, ctx, size=(96, 72), knobs={"post_path": "compute"})
    assert len(renderer.plan.post_passes) == 2 and all(p.path == "compute" for p in renderer.plan.post_passes)
    target = renderer.create_output()
    shared = run_frame(ctx, renderer.record, target).pixels
    calls = steady_calls(ctx, renderer.record, target)
    assert calls["encoder.begin_compute_pass"] == 1 and calls["compute_pass.dispatch_workgroups"] == 2, dict(calls)
    separate = run_frame(ctx, renderer.record, renderer.create_output(), timer=PassTimer(ctx)).pixels
    np.testing.assert_array_equal(shared, separate)
    assert (shared[..., :3].astype(int).sum(-1) > 30).mean() > 0.05, "the scene is drawn"
