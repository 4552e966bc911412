"""bench perf's rows for issue 31: the scale family's thread-CPU row, and the frame counts of the families whose
p99 is judged (wgpurender/bench/scale.py, wgpurender/bench/perf.py)."""

from __future__ import annotations

import time

import pytest

from wgpurender.bench import scale


def test_scale_case_reports_thread_cpu_beside_wall_cpu(ctx, tmp_path):
    """bench_case adds a cpu_thread_ms row (record + submit in thread CPU time) with one sample per timed frame,
    each a positive part of the thread's CPU time."""
    size = (32, 24)
    rows = scale.bench_case(ctx, scale.instanced_scene(tmp_path, 8, size), "instanced/8", size, frames=6)
    by_metric = {r.metric: r for r in rows}
    thread = by_metric["cpu_thread_ms"]
    assert (thread.family, thread.case, thread.path, thread.size, thread.n) == ("scene-scale", "instanced/8", "wgpu",
                                                                              "32x24", 6)
    assert 0 < thread.p10 <= thread.median <= thread.p90
    assert thread.n * thread.p10 <= time.thread_time() * 1e3  # per frame: no sample holds the thread's whole CPU time


@pytest.mark.parametrize(("kind", "family", "config", "want"), [
    ("DiscreteGPU", "scene", {}, 100), ("DiscreteGPU", "frames", {}, 100), ("DiscreteGPU", "scene-scale", {}, 100),
    ("DiscreteGPU", "objects", {}, 20), ("CPU", "scene", {}, 20), ("DiscreteGPU", "scene", {"frames": 7}, 7),
    ("DiscreteGPU", "scene", {"quick": True}, 4)])
def test_judged_tail_rows_get_enough_frames_for_a_p99_on_a_gpu(kind, family, config, want):
    """The p99 of 20 samples is their largest: the families whose p99 is judged time 100 frames a case on a GPU
    (--frames and --quick still decide when given)."""
    from types import SimpleNamespace

    from wgpurender.bench.perf import PerfConfig

    ctx = SimpleNamespace(adapter=SimpleNamespace(info={"adapter_type": kind}))
    assert PerfConfig(**config).timed_frames(ctx, family) == want
