"""Issue 31's paired pygfx row (bench/scale_paired.py), its SM clock (bench/sm_clock.py) and its goal row
(bench/markdown_pygfx.py). Stand-in sides advance a fake timer by frame times set here, so every expected value
is the set times' arithmetic; the real family runs on lavapipe when pygfx is installed."""

from __future__ import annotations

import math
import statistics
import subprocess
from types import SimpleNamespace

import pytest

from wgpurender.bench import markdown_pygfx, scale_paired, sm_clock
from wgpurender.bench.report import Result


class FakeTime:
    """A timer that moves only when a stand-in side draws: each side's frame takes the ms set for the round."""

    def __init__(self) -> None:
        self.now, self.log, self.round = 0.0, [], -1

    def __call__(self) -> float:
        return self.now

    def clock(self, readings):
        def read() -> str:
            self.round += 1
            self.log.append("clock")
            return readings[self.round]
        return read

    def side(self, name: str, ms_of_round, first_ms=None):
        """A draw: ``ms_of_round(k)`` ms a frame in round k; the round's first (untimed) frame ``first_ms``."""
        drawn = {}

        def draw() -> None:
            k = self.round
            first = drawn.get(k, 0) == 0
            drawn[k] = drawn.get(k, 0) + 1
            self.log.append(name)
            self.now += (first_ms if first and first_ms is not None else ms_of_round(k)) / 1e3
        return draw


def test_each_round_reads_the_clock_first_then_draws_both_sides_in_flipped_order():
    t = FakeTime()
    sides = {"wgpu": t.side("wgpu", lambda k: 2.0), "pygfx": t.side("pygfx", lambda k: 8.0)}
    rounds = scale_paired.paired_rounds(sides, rounds=4, frames=3, timer=t, clock=t.clock(["1980"] * 4))
    per_round = 1 + 2 * (1 + 3)  # the clock, then each side's untimed frame and 3 timed ones
    assert len(t.log) == 4 * per_round
    for k in range(4):
        chunk = t.log[k * per_round:(k + 1) * per_round]
        first, second = ("wgpu", "pygfx") if k % 2 == 0 else ("pygfx", "wgpu")
        assert chunk == ["clock"] + [first] * 4 + [second] * 4
        assert rounds[k].first == first
    assert [r.ratio for r in rounds] == pytest.approx([0.25] * 4)
    assert [r.ms["wgpu"] for r in rounds] == pytest.approx([2.0] * 4)


def test_the_untimed_first_frame_of_a_round_is_not_a_sample():
    t = FakeTime()
    sides = {"wgpu": t.side("wgpu", lambda k: 3.0, first_ms=100.0),
             "pygfx": t.side("pygfx", lambda k: 6.0, first_ms=100.0)}
    rounds = scale_paired.paired_rounds(sides, rounds=2, frames=1, timer=t, clock=t.clock(["?"] * 2))
    assert [r.ms for r in rounds] == [pytest.approx({"wgpu": 3.0, "pygfx": 6.0})] * 2


def test_a_clock_drop_between_rounds_moves_both_sides_and_not_the_ratio():
    # rounds 0-4 at full clock, 5-9 at half: every frame twice as long. A sequential pair of medians taken in
    # rounds 0 and 9 would read 2 / (2 * 8) = 0.125; each round's ratio is 2 / 8.
    t = FakeTime()
    slow = lambda k: 2.0 if k >= 5 else 1.0  # noqa: E731
    sides = {"wgpu": t.side("wgpu", lambda k: 2.0 * slow(k)), "pygfx": t.side("pygfx", lambda k: 8.0 * slow(k))}
    clocks = ["1980"] * 5 + ["1080"] * 5
    rows = scale_paired.paired_rows(
        scale_paired.paired_rounds(sides, rounds=10, frames=3, timer=t, clock=t.clock(clocks)), 10_000, (800, 600), 3)
    by = {(r.case, r.metric): r for r in rows}
    ratio = by[("ratio/10000", scale_paired.PAIRED)]
    assert (ratio.median, ratio.p10, ratio.p90, ratio.n) == pytest.approx((0.25, 0.25, 0.25, 10))
    wgpu = by[("instanced/10000", scale_paired.PAIRED_FRAME)]
    assert wgpu.median == pytest.approx(statistics.median([2.0] * 5 + [4.0] * 5))
    assert by[("pygfx/10000", scale_paired.PAIRED_FRAME)].path == "pygfx"
    clock = by[("ratio/10000", scale_paired.CLOCK)]
    assert (clock.median, clock.p10, clock.p90, clock.n) == (1530, 1080, 1980, 10)
    assert "SM clock 1080-1980 MHz" in ratio.note


def test_the_row_is_the_median_of_round_ratios_not_the_ratio_of_medians():
    # wgpu 1, 2, 3 ms and pygfx 4, 2, 12 ms: ratios 0.25, 1.0, 0.25 -> median 0.25; medians 2 / 4 = 0.5.
    wgpu, pygfx = [1.0, 2.0, 3.0], [4.0, 2.0, 12.0]
    t = FakeTime()
    sides = {"wgpu": t.side("wgpu", lambda k: wgpu[k]), "pygfx": t.side("pygfx", lambda k: pygfx[k])}
    rows = scale_paired.paired_rows(
        scale_paired.paired_rounds(sides, rounds=3, frames=2, timer=t, clock=t.clock(["?"] * 3)), 50, (64, 64), 2)
    ratio = next(r for r in rows if r.metric == scale_paired.PAIRED)
    assert ratio.median == pytest.approx(0.25)
    assert ratio.p90 > 0.8  # the 1.0 round is in the spread
    clock = next(r for r in rows if r.metric == scale_paired.CLOCK)
    assert clock.n == 0 and math.isnan(clock.median) and clock.note == sm_clock.NO_CLOCK


def test_sm_clock_reads_nvidia_smi_and_says_when_it_cannot(monkeypatch):
    answers = iter([SimpleNamespace(stdout="1980\n1755\n"), SimpleNamespace(stdout="[N/A]\n"),
                    SimpleNamespace(stdout="")])
    monkeypatch.setattr(subprocess, "run", lambda *a, **k: next(answers))
    assert sm_clock.sm_clock() == "1980"
    assert sm_clock.sm_clock() == "?"
    assert sm_clock.sm_clock("") == ""

    def missing(*a, **k):
        raise FileNotFoundError("nvidia-smi")
    monkeypatch.setattr(subprocess, "run", missing)
    assert sm_clock.sm_clock() == "?"


def test_clock_span():
    assert sm_clock.clock_span(["1980", "?", "1080", "1410"]) == "SM clock 1080-1980 MHz"
    assert sm_clock.clock_span(["1980", "1980"]) == "SM clock 1980 MHz"
    assert sm_clock.clock_span(["?", ""]) == sm_clock.NO_CLOCK


def _row(case, path, metric, median, p10=None, p90=None, n=1, note=""):
    return Result("scene-scale", case, path, "800x600", metric, median, median if p10 is None else p10,
                  median if p90 is None else p90, n, note)


def _judge(met, applies=""):
    return f"not judged ({applies})" if applies else ("met" if met else "not met")


def test_the_goal_is_judged_on_the_paired_row_and_the_sequential_one_is_reported():
    res = [_row("ratio/10000", "wgpu/pygfx", "frame_ratio", 0.24),  # sequential: would meet
           _row("ratio/10000", "wgpu/pygfx", scale_paired.PAIRED, 0.52, 0.48, 0.61, 10),  # paired: does not
           _row("instanced/10000", "wgpu", scale_paired.PAIRED_FRAME, 2.5),
           _row("pygfx/10000", "pygfx", scale_paired.PAIRED_FRAME, 4.8),
           _row("ratio/10000", "wgpu/pygfx", scale_paired.CLOCK, 1530, 1080, 1980, 10)]
    rows = markdown_pygfx.pygfx_targets(res, _judge)
    assert rows[0] == (markdown_pygfx.TITLE, "0.52x, paired over 10 interleaved rounds [p10 0.48..p90 0.61]; medians "
                       "2.500 / 4.800 ms; SM clock 1080-1980 MHz", "not met")
    assert rows[1][1].startswith("0.24x") and rows[1][2] == "reported"
    res[1] = _row("ratio/10000", "wgpu/pygfx", scale_paired.PAIRED, 0.45, 0.40, 0.50, 10)
    assert markdown_pygfx.pygfx_targets(res, _judge)[0][2] == "met"


def test_a_run_without_paired_rounds_is_shown_and_not_judged():
    rows = markdown_pygfx.pygfx_targets([_row("ratio/10000", "wgpu/pygfx", "frame_ratio", 0.24)], _judge)
    assert rows == [(markdown_pygfx.TITLE, "0.24x (frame with readback, medians measured one after the other, same "
                     "run)", "not judged (no paired rounds in this run)")]
    assert markdown_pygfx.pygfx_targets([], _judge) == []


def test_the_clock_text():
    assert markdown_pygfx.clock_text(None) == "SM clock not recorded"
    assert markdown_pygfx.clock_text(_row("r", "p", "sm_clock_mhz", 1980, 1980, 1980, 3)) == "SM clock 1980 MHz"
    nan = float("nan")
    assert markdown_pygfx.clock_text(_row("r", "p", "sm_clock_mhz", nan, nan, nan, 0, "why")) == "why"


def test_the_real_family_on_this_adapter(ctx):
    pytest.importorskip("pygfx")
    from wgpurender.bench.scale_pygfx import pygfx_pair

    lines = []
    rows, notes = scale_paired.bench_paired(ctx, [50], (64, 48), pygfx_pair(), rounds=2, frames=2, log=lines.append)
    by = {(r.case, r.path, r.metric): r for r in rows}
    ratio = by[("ratio/50", "wgpu/pygfx", scale_paired.PAIRED)]
    mine, theirs = by[("instanced/50", "wgpu", scale_paired.PAIRED_FRAME)], by[("pygfx/50", "pygfx",
                                                                                 scale_paired.PAIRED_FRAME)]
    assert ratio.n == mine.n == theirs.n == 2 and mine.median > 0 and theirs.median > 0
    assert 0 < ratio.median < 100
    clock = by[("ratio/50", "wgpu/pygfx", scale_paired.CLOCK)]
    if ctx.adapter.info["adapter_type"] == "CPU":
        assert clock.n == 0 and clock.note == sm_clock.NO_CLOCK
    assert lines == ["  scene-scale: paired wgpu/pygfx 50"] and len(notes) == 1


def test_without_pygfx_the_family_says_so_in_one_line(ctx, monkeypatch):
    from wgpurender.bench import scale

    assert scale_paired.bench_paired(ctx, [50], (64, 48), None) == ([], [])
    monkeypatch.setattr(scale, "bench_case", lambda *a, **k: [])
    monkeypatch.setattr(scale, "warm_up", lambda *a, **k: None)
    _, notes = scale.bench_scale(ctx, [8], 2, (64, 48), log=lambda s: None, peer=None)
    assert [n for n in notes if "pygfx" in n] == [
        "scene-scale: pygfx is not installed (pip install 'wgpurender[bench]'): no pygfx rows"]


def test_a_side_s_round_is_the_median_of_its_timed_frames():
    times = iter([0.0, 0.001, 0.001, 0.002, 0.002, 0.012])  # timed frames of 1, 1 and 10 ms
    assert scale_paired._median_frame(lambda: None, 3, lambda: next(times)) == pytest.approx(1.0)


def test_bench_perf_s_scene_scale_carries_the_paired_rows_and_notes(monkeypatch):
    from wgpurender.bench import perf, scale, scale_pygfx

    mine = _row("ratio/50", "wgpu/pygfx", scale_paired.PAIRED, 0.3)
    monkeypatch.setattr(scale, "bench_scale", lambda *a, **k: ([], ["sequential"]))
    monkeypatch.setattr(scale_pygfx, "pygfx_pair", lambda: "side")
    monkeypatch.setattr(scale_paired, "bench_paired",
                        lambda ctx, counts, size, side, log: ([mine], [f"paired {counts} {side}"]))
    run = perf.PerfRun(perf.PerfConfig(counts=(50,)), {})
    perf._scene_scale(None, run.config, run, lambda s: None)
    assert run.results == [mine] and run.notes == ["sequential", "paired [50] side"]
