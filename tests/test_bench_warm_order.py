"""The first timed frame of each round follows warm frames (issue 31.4, p99 <= 2x the median).

bench/frames.py's ``measure`` collected the garbage and read the timer's timestamps after the warm-up, right before
the first timed frame: that frame was each round's slowest (on lavapipe 6-17 ms against medians of 0.2-0.4 ms,
benchmarks/tail_probe.py), 4 of 100 samples, so the p99. A stand-in runner records what happens in order; GPU
times must still be those of the timed frames only.
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
    assert set(between) == {"frame", "readback"}
    warm = len(between) - 5 - 2
    assert warm >= bench_frames.WARM_WINDOW  # stable over a window of frames before any sample


def test_the_gpu_samples_are_the_timed_frames_only(monkeypatch):
    """Warm-up and readback frames drawn since the last read are not GPU samples."""
    events, gpu, _ = _run(monkeypatch, frames=4, readback_frames=1)
    numbered = [i + 1 for i, e in enumerate(events) if e in ("frame", "readback")]
    timed = [i + 1 for i, e in enumerate(events) if e == "frame"][-4:]
    assert len(numbered) > 5 and gpu == [float(n) for n in timed]
