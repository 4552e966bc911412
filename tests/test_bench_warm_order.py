"""Nothing the bench does itself comes between two timed frames (issue 31.4, p99 <= 2x the median).

bench/frames.py's ``measure`` collected the garbage and read the timer's timestamps after the warm-up, right before
the first timed frame: that frame was each round's slowest (on lavapipe 6-17 ms against medians of 0.2-0.4 ms,
benchmarks/tail_probe.py), 4 of 100 samples, so the p99. And half the samples followed a frame with readback. Now
the warm-up comes last before the samples and the readback pairs after them. A stand-in runner records what happens
in order; GPU times must still be those of the timed frames only, the readback cost each pair's difference.
"""

from __future__ import annotations

from wgpurender.bench import frames as bench_frames


class Recorder:
    """A runner that logs each call; a frame's GPU time is its number (warm-up frames are numbered too)."""

    def __init__(self, events: list[str]) -> None:
        self.events = events
        self.drawn: list[float] = []
        self.timed = False

    def frame(self, readback: bool = False) -> tuple[float, None]:
        self.events.append("readback" if readback else "frame")
        self.drawn.append(float(len(self.events)))
        return 0.1, None

    def collect_gpu(self) -> list[float]:
        self.events.append("collect")
        out, self.drawn = self.drawn, []
        return out


def _run(monkeypatch, frames: int, readback_frames: int) -> tuple[list[str], list[float], Recorder]:
    events: list[str] = []
    monkeypatch.setattr(bench_frames, "settle_garbage", lambda: events.append("settle"))
    runner = Recorder(events)
    samples = bench_frames.measure(runner, frames, warmup=2, readback_frames=readback_frames)
    return events, samples.gpu, runner


def test_nothing_but_frames_comes_between_the_warm_up_and_the_timed_frames(monkeypatch):
    events, _, _ = _run(monkeypatch, frames=5, readback_frames=2)
    first_frame = events.index("frame")
    assert set(events[:first_frame]) == {"settle", "collect"}  # the disruptions come first
    assert events[-1] == "collect"  # the timed frames' timestamps are read after them
    between = events[first_frame:-1]
    assert between[-4:] == ["frame", "readback", "frame", "readback"]  # the pairs last
    assert set(between[:-4]) == {"frame"}  # warm-up, then the 5 samples: no readback before any sample
    assert len(between) - 4 - 5 >= bench_frames.WARM_WINDOW  # stable over a window of frames before any sample


def _samples(events: list[str], frames: int) -> list[int]:
    """The event numbers (1-based) of the timed frames: the last ``frames`` frames that are not a pair's first."""
    partners = {i - 1 for i, e in enumerate(events) if e == "readback"}
    plain = [i + 1 for i, e in enumerate(events) if e == "frame" and i not in partners]
    return plain[-frames:]


def test_the_gpu_samples_are_the_timed_frames_only(monkeypatch):
    """Warm-up frames and readback pairs drawn since the last read are not GPU samples."""
    events, gpu, _ = _run(monkeypatch, frames=4, readback_frames=3)
    assert events.count("readback") == 3 and events.count("frame") >= 4 + 3 + bench_frames.WARM_WINDOW
    assert gpu == [float(n) for n in _samples(events, 4)]


def test_the_readback_cost_is_each_readback_frame_minus_the_frame_just_before_it(monkeypatch):
    """Frame times from a clock the stand-in advances: plain frames 1 ms, readback frames 3 ms; 2 pairs."""
    clock = [0.0]
    monkeypatch.setattr(bench_frames.time, "perf_counter", lambda: clock[0])
    events: list[str] = []
    monkeypatch.setattr(bench_frames, "settle_garbage", lambda: None)

    class Clocked(Recorder):
        def frame(self, readback: bool = False):
            clock[0] += 0.003 if readback else 0.001
            return super().frame(readback)

    samples = bench_frames.measure(Clocked(events), 3, warmup=2, readback_frames=2)
    assert [round(v, 9) for v in samples.frame] == [1.0, 1.0, 1.0]
    assert [round(v, 9) for v in samples.readback_frame] == [3.0, 3.0]
    assert [round(v, 9) for v in samples.readback_pair] == [2.0, 2.0]
