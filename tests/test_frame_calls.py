"""The final scene's steady-state frame costs a handful of native calls (issue 22.2), on both post paths.

Counted by wrapping the device, queue and encoders (wgpurender/bench/calls.py), not by timing: the static
draws replay from render bundles, bind groups and views are made once, the camera is uploaded only when it
changes, and a steady frame creates nothing. The pinned numbers are the ones reached (a regression
shows as a larger count; a smaller one should lower the pin).
"""

from __future__ import annotations

from pathlib import Path

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
