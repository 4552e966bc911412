"""The frame4 pass's probes (issue 31.4): benchmarks/record_ahead_probe.py (frames recorded one ahead, the thread
pinned) and benchmarks/cold_frame_probe.py (the same native calls replayed without Python, a wait in naps).

Their numbers are the H100's (docs/perf-h100/2026-11-27-frame4/); what is tested here is that each structure they
compare draws the frame it claims: the same calls in the order claimed, the same pixels as a frame recorded after
the wait, and spans summed as the docs read them. The replay's first try on the H100 failed validation: wgpu-py's
pass encoders call set_bind_group through a class attribute the capture did not see (the compute post path)."""

from __future__ import annotations

import importlib
import os
import statistics
import time
from pathlib import Path

import numpy as np
import pytest

from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.device.targets import read_texture
from wgpurender.wgpu_path.scene import load_renderer

REPO = Path(__file__).resolve().parent.parent
FINAL = REPO / "assets" / "scenes" / "final.toml"


def _scripts(monkeypatch, *names: str):
    """benchmarks/<name>.py as modules, their folder on the path: they import each other and probe_csv from it
    (helpers.benchmark_script imports a lone script)."""
    monkeypatch.syspath_prepend(str(REPO / "benchmarks"))
    return tuple(importlib.import_module(name) for name in names)


@pytest.fixture
def probes(monkeypatch):
    """The two probe scripts as modules."""
    return _scripts(monkeypatch, "record_ahead_probe", "cold_frame_probe")


class _Log:
    """A stand-in context whose device, encoders and queue write what happens into ``events``."""

    def __init__(self) -> None:
        self.events, self.made = [], 0
        self.device, self.queue = self, self

    def create_command_encoder(self, label: str = ""):
        self.made += 1
        number, events = self.made, self.events
        events.append(("encoder", number))

        class Encoder:
            def finish(self):
                events.append(("finish", number))
                return f"buffer {number}"

        return Encoder()

    def submit(self, buffers):
        self.events.append(("submit", *buffers))


def test_frames_ahead_submits_the_frame_recorded_before_and_records_the_next_at_its_time(probes):
    ahead_module, _ = probes
    log = _Log()
    ahead = ahead_module.FramesAhead(log, lambda encoder, target, t: log.events.append(("record", target, t)), "T")
    ahead.frame(0.5)
    assert log.events == [("encoder", 1), ("record", "T", 0.5), ("finish", 1), ("submit", "buffer 1"),
                          ("encoder", 2), ("record", "T", 0.5), ("finish", 2)]
    del log.events[:]
    ahead.frame(1.0, t_next=2.0)  # the frame recorded at 0.5 goes now; the next is recorded for 2.0
    assert log.events == [("submit", "buffer 2"), ("encoder", 3), ("record", "T", 2.0), ("finish", 3)]
    del log.events[:]
    ahead.drop()
    ahead.submit(3.0)  # nothing ahead: recorded at 3.0, submitted, and nothing is left pending
    assert log.events == [("encoder", 4), ("record", "T", 3.0), ("finish", 4), ("submit", "buffer 4")]
    assert ahead.pending is None


@pytest.mark.parametrize("post_path", ["fragment", "compute"])
def test_each_structure_draws_the_frame_recorded_after_the_wait(ctx, probes, post_path):
    """Today's frame, the frame recorded ahead, the native replay and the napping wait: the same pixels, each
    drawn into a target zeroed first (so an empty replay cannot pass as the last structure's image)."""
    ahead_module, cold = probes
    renderer = load_renderer(FINAL, ctx, size=(96, 72), knobs={"post_path": post_path})
    target = renderer.create_output()
    expected = run_frame(ctx, renderer.record, target).pixels
    assert (expected[..., :3].astype(int).sum(-1) > 30).mean() > 0.05, "the scene is drawn"
    ahead = ahead_module.FramesAhead(ctx, renderer.record, target)
    native = cold.NativeFrame(ctx, renderer.record, target)
    structures = {
        "after_wait": lambda: ahead_module.after_wait(ctx, renderer.record, target, 0.0),
        "ahead": lambda: ahead_module.ahead_frame(ctx, ahead, 0.0),
        "native": lambda: cold.native_frame(ctx, native),
        "naps": lambda: cold.napping_frame(ctx, renderer.record, target, 0.002),
    }
    for name, frame in structures.items():
        ahead_module.wipe(ctx, target)
        assert not read_texture(ctx, target).any(), "the wipe leaves zeros"
        frame()
        np.testing.assert_array_equal(read_texture(ctx, target), expected, err_msg=name)
    assert ahead.pending is not None  # the next frame waits, finished, for its submit
    ahead_module.wipe(ctx, target)
    ahead.submit(0.0)
    ctx.wait_idle()
    np.testing.assert_array_equal(read_texture(ctx, target), expected)


def test_the_native_replay_makes_the_calls_of_the_wgpu_py_frame(ctx, probes):
    """The compute path's frame: its set_bind_group calls (made through a class attribute) are captured too."""
    _, cold = probes
    renderer = load_renderer(FINAL, ctx, size=(96, 72), knobs={"post_path": "compute"})
    target = renderer.create_output()
    run_frame(ctx, renderer.record, target)
    names = [fn.__name__ for fn, _, _ in cold.NativeFrame(ctx, renderer.record, target).calls]
    dispatches = len(renderer.plan.post_passes)
    assert names.count("wgpuComputePassEncoderSetBindGroup") == dispatches
    assert names.count("wgpuComputePassEncoderDispatchWorkgroups") == dispatches
    assert names[0] == "wgpuDeviceCreateCommandEncoder" and names[-1] == "wgpuQueueSubmit"
    assert not any(name.endswith("Release") for name in names)  # the replay releases its own handles


def test_the_napping_wait_sleeps_until_its_share_of_the_expected_frame(ctx, probes):
    ahead_module, cold = probes
    renderer = load_renderer(FINAL, ctx, size=(32, 24), knobs={"post_path": "fragment"})
    target = renderer.create_output()
    plain = min(run_frame(ctx, renderer.record, target, wait=True).frame_ms for _ in range(3)) / 1e3
    expected = max(0.05, 20 * plain)  # far longer than the frame itself: the naps make the difference
    start = time.perf_counter()
    spans = cold.napping_frame(ctx, renderer.record, target, expected)
    took = time.perf_counter() - start
    assert took >= cold.NAP_UNTIL * expected
    assert all(s >= 0 for s in spans) and spans[0] + spans[2] < took


def test_the_rows_sum_the_spans_of_a_frame_into_its_cpu(probes):
    ahead_module, _ = probes
    # (record wall, record thread, submit wall, submit thread) in seconds; frame k's record is k ms
    spans = [(k / 1e3, k / 2e3, 0.5e-3, 0.25e-3) for k in range(1, 101)]
    row = ahead_module.rows_for("s", "8x8", spans, [2.0] * 100, {"h"})
    cpu = [k + 0.5 for k in range(1, 101)]
    assert row["cpu_wall_ms"] == pytest.approx(statistics.median(cpu))
    assert row["cpu_wall_p99_ms"] == pytest.approx(sorted(cpu)[99])
    assert row["cpu_thread_ms"] == pytest.approx(statistics.median(k / 2 + 0.25 for k in range(1, 101)))
    assert row["record_wall_ms"] == pytest.approx(50.5) and row["submit_thread_ms"] == pytest.approx(0.25)
    assert row["frames"] == 100 and row["frame_ms"] == 2.0 and row["image_sha256"] == "h"
    few = ahead_module.rows_for("s", "8x8", spans[:10], [1.0] * 10, {"b", "a"})
    assert few["cpu_wall_p99_ms"] == pytest.approx(10.5) and few["image_sha256"] == "a/b"


def test_this_cpu_is_one_the_thread_may_run_on(probes):
    ahead_module, _ = probes
    assert ahead_module.this_cpu() in os.sched_getaffinity(0)


@pytest.fixture
def python_calls(monkeypatch):
    return _scripts(monkeypatch, "frame_python_calls")[0]


def test_each_function_is_counted_for_whoever_wrote_it(python_calls):
    owner = python_calls.owner
    assert owner("~") == "builtins"
    assert owner("/x/site-packages/wgpu/backends/wgpu_native/_api.py") == "wgpu-py"
    assert owner("/x/wgpurender/wgpu_path/scene/frame.py") == "wgpurender"
    assert owner("/x/site-packages/cffi/api.py") == "cffi"
    assert owner("/usr/lib/python3.11/weakref.py") == "stdlib"
    assert owner("/x/wgpu_helpers/wgpurender_notes.py") == "stdlib"  # a name that only contains the words


def test_the_frame_s_python_calls_are_counted_per_frame(ctx, python_calls):
    renderer = load_renderer(FINAL, ctx, size=(32, 24), knobs={"post_path": "compute"})
    counts = python_calls.calls_per_frame(ctx, renderer, 4)
    # ours per frame: the renderer's record, its bound frame and the scene pass's and chain's records, a dispatch
    # per planned pass (the exact set may change; a frame of ours stays a handful, wgpu-py's far more)
    assert 3 + len(renderer.plan.post_passes) <= counts["wgpurender"] <= 20
    assert counts["wgpu-py"] > 5 * counts["wgpurender"]
    assert counts["builtins"] > 0 and counts["wgpurender"] == int(counts["wgpurender"])  # the same every frame


def test_the_rounds_flip_the_order_zero_the_target_and_pin_only_the_pinned(ctx, probes):
    ahead_module, _ = probes
    renderer = load_renderer(FINAL, ctx, size=(32, 24), knobs={"post_path": "fragment"})
    target = renderer.create_output()
    allowed, seen = os.sched_getaffinity(0), []

    def draws():
        seen.append(("draws", len(os.sched_getaffinity(0))))
        return ahead_module.after_wait(ctx, renderer.record, target, 0.0)

    def nothing_pinned():
        seen.append(("nothing_pinned", len(os.sched_getaffinity(0))))
        return (0.001, 0.001, 0.0005, 0.0005)

    ahead = ahead_module.FramesAhead(ctx, renderer.record, target)
    rows = ahead_module.run_rounds(ctx, target, {"draws": draws, "nothing_pinned": nothing_pinned}, ahead, 4, 2,
                                   "32x24")
    per_round = ahead_module.WARM + 2
    blocks = [seen[i][0] for i in range(0, len(seen), per_round)]
    assert blocks == ["draws", "nothing_pinned", "nothing_pinned", "draws"]
    assert {n for name, n in seen if name == "nothing_pinned"} == {1}
    assert {n for name, n in seen if name == "draws"} == {len(allowed)} and os.sched_getaffinity(0) == allowed
    by_name = {r["structure"]: r for r in rows}
    assert by_name["draws"]["frames"] == 4 and by_name["nothing_pinned"]["cpu_wall_ms"] == pytest.approx(1.5)
    ahead_module.wipe(ctx, target)
    zeros = ahead_module.image_hash(ctx, target)
    assert by_name["nothing_pinned"]["image_sha256"] == zeros  # zeroed before its round: it drew nothing
    assert by_name["draws"]["image_sha256"] != zeros
    assert by_name["draws"]["wait_thread_ms"] >= 0  # the thread CPU of the frame less its spans
