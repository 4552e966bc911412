"""bench perf's control family (issue 31.4's p99 goal): the host's own tail, sampled as the frame rows are, with no
renderer in it (wgpurender/bench/control.py), its row in the goal table (markdown_scale.control_row), and
``--counts`` (the scene-scale counts a run takes)."""

from __future__ import annotations

import gc
import statistics
import time
import zlib
from types import SimpleNamespace

import pytest

from wgpurender.bench import control, markdown_scale
from wgpurender.bench.report import Result
from wgpurender.core.scene.model import MAX_INSTANCES


def _crc_ms(size: int, runs: int = 21) -> float:
    """A crc32 over ``size`` bytes, timed here on its own: the median of ``runs`` (the test's own clock loop)."""
    data = bytes(size)
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        zlib.crc32(data)
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times)


def test_the_cpu_rows_time_the_workload_itself(ctx):
    """Each control row has one sample per timed frame; the fixed workload's median is a crc32 over its bytes as
    timed separately here (within 2.5x either way, on a shared machine), and the round trip's CPU part is no more
    than its frame."""
    rows = {(r.case, r.metric): r for r in control.bench_control(ctx, 12)}
    assert set(rows) == {("cpu-fixed", "frame_ms"), ("cpu-fixed", "cpu_ms"), ("gpu-empty", "frame_ms"),
                         ("gpu-empty", "cpu_ms")}
    assert {(r.family, r.size, r.n) for r in rows.values()} == {("control", "", 12)}
    fixed = rows[("cpu-fixed", "cpu_ms")]
    size = int(fixed.note.split(" over ")[1].split()[0])
    alone = _crc_ms(size)
    assert alone / 2.5 <= fixed.median <= alone * 2.5, (fixed.median, alone, size)
    assert fixed.median <= rows[("cpu-fixed", "frame_ms")].median * 1.01
    assert 0 < rows[("gpu-empty", "cpu_ms")].median <= rows[("gpu-empty", "frame_ms")].median


def test_the_calibrated_workload_takes_about_the_target():
    size = control.calibrated_bytes(0.3)
    assert size % 1024 == 0 and control.PROBE_BYTES <= size <= control.MAX_BYTES
    alone = _crc_ms(size)
    assert 0.3 / 3 <= alone <= 0.3 * 3, (size, alone)
    assert control.calibrated_bytes(1.2) > 2 * size  # 4x the time, well over twice the bytes on any load


def test_the_cpu_workload_is_the_same_crc_every_frame():
    work = control.CpuWorkload(8192)
    assert len(work.buffer) == 8192
    ms, gpu = work.frame()
    assert gpu is None and ms > 0 and work.checksum == zlib.crc32(bytes(range(256)) * 32)


def test_controls_are_sampled_as_the_frame_rows(monkeypatch):
    """Through frames.measure: warm-up frames first (untimed), then ``frames`` samples with the collector paused
    (as $WGPURENDER_BENCH_GC leaves it by default), and the collector back on afterwards."""
    from wgpurender.bench.frames import GC_ENV

    monkeypatch.delenv(GC_ENV, raising=False)
    seen = []
    real = control.CpuWorkload.run
    monkeypatch.setattr(control.CpuWorkload, "run", lambda self: seen.append(gc.isenabled()) or real(self))
    fake = _fake_ctx([])
    was = gc.isenabled()
    gc.enable()
    try:
        rows = control.bench_control(fake, 9)
        assert gc.isenabled()
    finally:
        if not was:
            gc.disable()
    assert {r.n for r in rows} == {9}
    warm = len(seen) - 9
    assert warm >= 2 and seen[warm:] == [False] * 9, seen


def _fake_ctx(events: list, wait_s: float = 0.0):
    encoder = SimpleNamespace(finish=lambda: events.append("finish") or "commands")

    def wait():
        events.append("wait")
        time.sleep(wait_s)

    return SimpleNamespace(
        device=SimpleNamespace(create_command_encoder=lambda label=None: events.append("encoder") or encoder),
        queue=SimpleNamespace(submit=lambda buffers: events.append(("submit", tuple(buffers)))), wait_idle=wait)


def test_the_round_trip_submits_an_empty_encoder_and_waits_outside_its_cpu_time():
    events = []
    trip = control.EmptyGpuRoundTrip(_fake_ctx(events, wait_s=0.02))
    start = time.perf_counter()
    cpu_ms, gpu = trip.frame()
    wall_ms = (time.perf_counter() - start) * 1e3
    assert events == ["encoder", "finish", ("submit", ("commands",)), "wait"]
    assert gpu is None and 0 < cpu_ms < 20 <= wall_ms


def test_the_round_trip_rows_time_the_round_trip():
    """gpu-empty's rows are the round trip's: its frame holds the GPU wait (2 ms here), its CPU part does not."""
    events = []
    rows = {(r.case, r.metric): r for r in control.bench_control(_fake_ctx(events, wait_s=0.002), 5)}
    assert rows[("gpu-empty", "frame_ms")].median >= 2 > rows[("gpu-empty", "cpu_ms")].median
    assert events.count("wait") >= 5 and events.count("encoder") == events.count("wait")


def test_run_perf_samples_the_control_as_many_times_as_the_frame_rows(monkeypatch):
    """bench perf's control step asks for the frame rows' count on a GPU adapter (100), not the default 20."""
    from wgpurender.bench import perf

    fake = _fake_ctx([])
    fake.adapter = SimpleNamespace(info={"adapter_type": "DiscreteGPU"})
    monkeypatch.setattr(perf, "machine_info", lambda ctx: {})
    run = perf.run_perf(perf.PerfConfig(families=("control",)), ctx=fake, log=lambda _: None)
    assert {(r.family, r.n) for r in run.results} == {("control", perf.TAIL_FRAMES)} and len(run.results) == 4


def test_control_family_gets_the_frame_rows_sample_count():
    from wgpurender.bench.perf import FAMILIES, TAIL_FRAMES, PerfConfig

    gpu = SimpleNamespace(adapter=SimpleNamespace(info={"adapter_type": "DiscreteGPU"}))
    config = PerfConfig()
    assert "control" in FAMILIES
    assert config.timed_frames(gpu, "control") == config.timed_frames(gpu, "frames") == TAIL_FRAMES


def _row(family: str, case: str, metric: str, median: float, p99: float, n: int = 100) -> Result:
    return Result(family, case, "wgpu", "", metric, median, median, (median + p99) / 2, n, "", p99)


def _targets(rows):
    return {t[0]: t[1:] for t in markdown_scale.targets(rows, lambda met, applies="": "met" if met else "not met")}


CONTROL_TITLE = "control: p99 <= 2x median with no renderer (sampled as the frame rows)"


@pytest.mark.parametrize(("gpu_p99", "over"), [(0.09, 0), (0.11, 1)])
def test_the_control_row_says_whether_the_host_itself_is_over(gpu_p99, over):
    frames = [_row("frames", "3d", "frame_ms", 1.0, 2.5), _row("frames", "3d", "cpu_ms", 0.2, 0.3),
              _row("scene-scale", "instanced/1000", "cpu_ms", 0.2, 0.5)]
    ctl = [_row("control", "cpu-fixed", "frame_ms", 0.3, 0.36), _row("control", "cpu-fixed", "cpu_ms", 0.3, 0.33),
           _row("control", "gpu-empty", "frame_ms", 0.05, gpu_p99), _row("control", "gpu-empty", "cpu_ms", 0.02, 0.03),
           _row("control", "gpu-empty", "gpu_ms", 0.01, 9.0), _row("control", "cpu-fixed", "cpu_ms", 0.3, 9.0, n=4)]
    got = _targets(frames + ctl)
    assert got["p99 <= 2x median in the frame rows (frame and CPU)"][0].startswith("2 of 3 rows over")  # not ctl's
    measured, status = got[CONTROL_TITLE]
    assert measured.startswith(f"{over} of 4 rows over: cpu-fixed frame 0.300 ms, p99 0.360 ms (1.20x); ")
    assert f"gpu-empty frame 0.050 ms, p99 {gpu_p99:.3f} ms ({gpu_p99 / 0.05:.2f}x)" in measured
    assert status == ("over: the host alone makes such tails" if over else "within: no host tail in this run")
    assert list(got).index(CONTROL_TITLE) == list(got).index("p99 <= 2x median in the frame rows (frame and CPU)") + 1


def test_no_control_rows_no_control_row():
    assert CONTROL_TITLE not in _targets([_row("frames", "3d", "frame_ms", 1.0, 2.5)])


# -- --counts ------------------------------------------------------------------------------------------------


@pytest.fixture
def nothing_runs(monkeypatch):
    """No bench runs and no GPU starts: a flag not refused fails the test at once rather than timing for minutes."""
    from wgpurender.bench import perf
    from wgpurender.wgpu_path.device import context

    monkeypatch.setattr(context, "get_context", lambda backend=None: SimpleNamespace(
        adapter=SimpleNamespace(info={"adapter_type": "CPU"})))

    def ran(*a, **k):
        raise AssertionError("the bench ran: the flag was not refused")

    monkeypatch.setattr(perf, "run_perf", ran)


@pytest.mark.parametrize(("args", "words"), [
    (["--only", "frames", "--counts", "1000"], "--only scene-scale"),
    (["--only", "scene-scale", "--counts", "1000,x"], "positive whole numbers"),
    (["--only", "scene-scale", "--counts", "0"], "positive whole numbers"),
    (["--only", "scene-scale", "--counts", ","], "positive whole numbers"),
    (["--only", "scene-scale", "--counts", "1000,\u00b2"], "positive whole numbers"),  # str.isdigit's, not int's
    (["--only", "scene-scale", "--counts", str(MAX_INSTANCES + 1)], f"at most {MAX_INSTANCES}"),
    (["--only", "scene-scale", "--counts", "1" + "0" * 40], f"at most {MAX_INSTANCES}"),
    (["--only", "scene-scale", "--counts", "9" * 5000], f"at most {MAX_INSTANCES}")])  # past int()'s 4300 digits
def test_bad_counts_are_one_line(capsys, tmp_path, nothing_runs, args, words):
    from wgpurender.cli import main

    out = tmp_path / "r"
    assert main(["bench", "perf", *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--counts" in err[0] and words in err[0], err
    assert not out.exists()


def test_counts_reach_the_scene_scale_family(monkeypatch, tmp_path):
    from wgpurender.bench import perf, scale
    from wgpurender.cli import main
    from wgpurender.wgpu_path.device import context

    got = {}
    monkeypatch.setattr(context, "get_context", lambda backend=None: SimpleNamespace(
        adapter=SimpleNamespace(info={"adapter_type": "CPU"})))
    monkeypatch.setattr(perf, "machine_info", lambda ctx: {})
    monkeypatch.setattr(scale, "bench_scale",
                        lambda ctx, counts, *a, **k: got.setdefault("counts", counts) and ([], []))
    monkeypatch.setattr("wgpurender.bench.scale_pygfx.pygfx_peer", lambda: None)
    monkeypatch.setattr("wgpurender.bench.scale_pygfx.pygfx_pair", lambda: None)
    assert main(["bench", "perf", "--only", "scene-scale", "--counts", "1000, 10000", "--out", str(tmp_path)]) == 0
    assert got["counts"] == [1000, 10000]
