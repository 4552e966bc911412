"""bench perf's rows for issue 31: the scale family's thread-CPU row, and the frame counts of the families whose
p99 is judged (wgpurender/bench/scale.py, wgpurender/bench/perf.py)."""

from __future__ import annotations

import time

import pytest

from wgpurender.bench import scale


def test_scale_case_reports_thread_cpu_beside_wall_cpu(ctx, tmp_path, monkeypatch):
    """bench_case adds a cpu_thread_ms row (record + submit in thread CPU time) with one sample per timed frame,
    each a positive part of the thread's CPU time."""
    size = (32, 24)
    monkeypatch.setattr(scale, "SAME_WAIT_MS", 150.0)  # a loaded machine's 32x24 frame fits, whatever the load
    rows = scale.bench_case(ctx, scale.instanced_scene(tmp_path, 8, size), "instanced/8", size, frames=6)
    by_metric = {r.metric: r for r in rows}
    thread = by_metric["cpu_thread_ms"]
    assert (thread.family, thread.case, thread.path, thread.size, thread.n) == ("scene-scale", "instanced/8", "wgpu",
                                                                              "32x24", 6)
    assert 0 < thread.p10 <= thread.median <= thread.p90
    assert thread.n * thread.p10 <= time.thread_time() * 1e3  # per frame: no sample holds the thread's whole CPU time
    same = by_metric[scale.SAME_WAIT]
    assert (same.case, same.n) == ("instanced/8", 6) and 0 < same.p10 <= same.median <= same.p90


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


def test_same_wait_rows_begin_every_frame_one_period_after_the_last(ctx, tmp_path, monkeypatch):
    """The same-wait row (issue 31.3's controlled comparison): every record begins one period after the one before,
    however short the frame, so the wait before it is the same at every count; one sample per timed frame; a frame
    longer than the period gives no row rather than a row with another wait."""
    size = (32, 24)
    from wgpurender.bench.scene import SceneRunner

    runner = SceneRunner(ctx, scale.instanced_scene(tmp_path, 8, size), size)
    runner.frame(readback=True)
    starts = []
    record_submit = scale._record_submit

    def stamped(runner_, clock):  # stamped where the frame begins, not inside the record (which a busy host delays)
        starts.append(time.perf_counter())
        return record_submit(runner_, clock)

    monkeypatch.setattr(scale, "_record_submit", stamped)
    period_ms = 150.0  # longer than any 32x24 frame here, however loaded the machine
    stats = scale.same_wait_cpu(runner, 5, period_ms)
    assert stats.n == 5 and 0 < stats.p10 <= stats.median <= stats.p90 < period_ms
    gaps = [(b - a) * 1e3 for a, b in zip(starts, starts[1:], strict=False)]
    # never sooner (later: the machine's sleep); 1 ms for a thread switch between the schedule's clock and the stamp
    assert len(gaps) == 6 and all(g >= period_ms - 1.0 for g in gaps), gaps
    assert scale.same_wait_cpu(runner, 5, 1e-3) is None  # no frame fits in a microsecond


def test_growth_is_judged_on_the_same_wait_row_where_the_run_has_it():
    """markdown_scale judges "does not grow" on the same-wait row when a run has it at two counts (the as-a-window
    row reported beside it), and on cpu_ms in older runs that lack it."""
    from wgpurender.bench import markdown_scale
    from wgpurender.bench.report import Result

    def row(n, metric, median):
        return Result("scene-scale", f"instanced/{n}", "wgpu", "800x600", metric, median, median, median, 10, "")

    def judge(met, applies=""):
        return "met" if met else "not met"

    window = [row(1000, "cpu_ms", 0.1), row(1000000, "cpu_ms", 0.4)]
    same = [row(1000, markdown_scale.SAME_WAIT, 0.3), row(1000000, markdown_scale.SAME_WAIT, 0.33)]
    old = {label: status for label, _, status in markdown_scale.targets(window, judge)}
    assert old == {"CPU per frame does not grow with the instance count": "not met"}
    new = [(label, status) for label, _, status in markdown_scale.targets(window + same, judge)]
    assert new[0] == ("CPU per frame does not grow with the instance count (same wait before every frame: the count "
                      "is the only variable)", "met")
    assert new[1] == ("CPU per frame vs the instance count, each frame after its own GPU wait", "reported")
    grown = [row(1000, markdown_scale.SAME_WAIT, 0.1), row(1000000, markdown_scale.SAME_WAIT, 0.2)]
    assert markdown_scale.targets(window + grown, judge)[0][2] == "not met"


def test_a_same_wait_row_missing_the_largest_count_is_not_the_judged_one():
    """A count whose frame is longer than the period has no same-wait row (scale.same_wait_cpu gives None): judging
    the counts left (1k to 100k) would call a 1M target met that was never measured under the same wait."""
    from wgpurender.bench import markdown_scale
    from wgpurender.bench.report import Result

    def row(n, metric, median):
        return Result("scene-scale", f"instanced/{n}", "wgpu", "800x600", metric, median, median, median, 10, "")

    counts = (1000, 10000, 100000, 1000000)
    window = [row(n, "cpu_ms", 0.1 * (k + 1)) for k, n in enumerate(counts)]  # 4x from the smallest to the largest
    flat = [row(n, markdown_scale.SAME_WAIT, 0.3) for n in counts[:-1]]  # none at the largest
    got = {label: (measured, status) for label, measured, status in markdown_scale.targets(window + flat, lambda m,
                                                                                           applies="": str(m))}
    judged = [(label, m) for label, (m, status) in got.items() if status != "reported"]
    assert judged == [("CPU per frame does not grow with the instance count",
                       f"0.100 ms at 1000, 0.400 ms at {counts[-1]} (4.00x)")], got
    same = [label for label in got if "same wait" in label]
    assert len(same) == 1 and got[same[0]][1] == "reported" and f"at {counts[-2]}" in got[same[0]][0]
    assert "does not grow" not in same[0], same  # a partial row does not claim the target's words


@pytest.mark.parametrize(("setting", "collector_on"), [(None, False), ("default", True)])
def test_the_scale_rows_follow_the_bench_gc_setting_as_the_other_frames_do(monkeypatch, setting, collector_on):
    """cpu_thread_ms and the same-wait row paused the collector with their own helper, which did not read
    $WGPURENDER_BENCH_GC: with it set to default (the collector as Python sets it) every other frame row ran with
    the collector and these two without, silently. A stand-in runner notes the collector's state at each record."""
    import gc
    from types import SimpleNamespace

    from wgpurender.bench.frames import GC_ENV

    if setting is None:
        monkeypatch.delenv(GC_ENV, raising=False)
    else:
        monkeypatch.setenv(GC_ENV, setting)
    seen = []
    encoder = SimpleNamespace(finish=lambda: None)
    ctx = SimpleNamespace(device=SimpleNamespace(create_command_encoder=lambda label=None: encoder),
                          queue=SimpleNamespace(submit=lambda buffers: None), wait_idle=lambda: None)
    runner = SimpleNamespace(ctx=ctx, target=None,
                             renderer=SimpleNamespace(record=lambda enc, target, t: seen.append(gc.isenabled())))
    was = gc.isenabled()
    gc.enable()
    try:
        scale.thread_cpu(runner, 3)
        scale.same_wait_cpu(runner, 3, 5.0)
        assert gc.isenabled(), "the collector is on again after the rows"
    finally:
        if not was:
            gc.disable()
    assert len(seen) == 10 and set(seen) == {collector_on}, seen


def test_scale_loads_a_warm_up_scene_of_each_kind_before_the_first_timed_load(ctx, monkeypatch):
    """The first load in a process pays the driver's first pipelines (2.4 s on a fresh H100 host): bench_scale loads
    a small instanced, batched and distinct scene, untimed and without rows, before the first timed case."""
    from wgpurender.bench import scene as bench_scene

    events = []
    real_runner = bench_scene.SceneRunner

    def runner(ctx_, path, size):
        events.append(("load", path.parent.name, path.stem))
        return real_runner(ctx_, path, size)

    monkeypatch.setattr(bench_scene, "SceneRunner", runner)
    monkeypatch.setattr(scale, "bench_case", lambda ctx_, path, case, size, frames: events.append(("timed", case))
                        or [])
    results, notes = scale.bench_scale(ctx, [3], frames=1, size=(16, 12), log=lambda _: None)
    kinds = [e for e in events if e[0] == "load"]
    assert kinds == [("load", "warm-up", f"instanced_{scale.WARM_UP_COUNT}"),
                     ("load", "warm-up", f"batched_{scale.WARM_UP_COUNT}"),
                     ("load", "warm-up", f"distinct_{scale.WARM_UP_COUNT}")]
    assert events.index(kinds[-1]) < events.index(("timed", "instanced/3")) and results == []
    assert any("untimed load" in n for n in notes)


def test_scale_times_batched_beside_instanced_and_distinct_up_to_its_limit(ctx, monkeypatch):
    """Every count has instanced/N; batched/N (N models of one file) and distinct/N up to their own limits on
    this adapter's kind (lavapipe: CPU; the H100: GPU; both set alike here), each named for its count."""
    timed = []
    monkeypatch.setattr(scale, "warm_up", lambda *a: None)
    monkeypatch.setattr(scale, "bench_case", lambda ctx_, path, case, size, frames: timed.append(
        (case, path.name)) or [])
    monkeypatch.setattr(scale, "BATCHED_LIMITS", {"CPU": 3, "GPU": 3})
    monkeypatch.setattr(scale, "DISTINCT_LIMITS", {"CPU": 20, "GPU": 20})
    kind = "CPU" if ctx.adapter.info["adapter_type"] == "CPU" else "GPU"
    _, notes = scale.bench_scale(ctx, [3, 20, 21], frames=1, size=(16, 12), log=lambda _: None)
    assert timed == [("instanced/3", "instanced_3.toml"), ("batched/3", "batched_3.toml"),
                     ("distinct/3", "distinct_3.toml"), ("instanced/20", "instanced_20.toml"),
                     ("distinct/20", "distinct_20.toml"), ("instanced/21", "instanced_21.toml")]
    assert any("batched" in n and f"stops at 3 on a {kind} adapter" in n for n in notes)
