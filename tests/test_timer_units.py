"""Every timer reports milliseconds: wall-clock statistics, and GPU timestamps on both paths.

A unit slip (seconds, microseconds or raw nanosecond ticks reported as milliseconds) is a factor of 1000,
so the checks bound each reading by a clock the test reads itself, with margins of 10x or more: they are
unit checks, not speed assertions, and hold on a loaded machine.
- wall_time around a 30 ms sleep: at least 29 ms (a sleep never ends early) and under 3 s.
- A GPU pass (4x MSAA triangle, 1024x1024) timed by timestamps on the wgpu path (PassTimer, through
  the bench's stage runner) and the raw path (vkCmdWriteTimestamp, RawStageRunner): no longer than the
  wall time the test measures around the whole frame (submit and wait included), and at least 1 us.
  On lavapipe the GPU is the CPU, so the pass is also most of that wall time (at least a tenth).
"""

from __future__ import annotations

import time

import pytest

from wgpurender.bench.frames import RawStageRunner, WgpuStageRunner
from wgpurender.wgpu_path.device.timing import wall_time

SIZE = (1024, 1024)


def test_wall_time_reports_milliseconds():
    stats = wall_time(lambda: time.sleep(0.030), warmup=0, repeats=3)
    assert 29.0 <= stats.p10 and stats.median < 3000.0, (
        f"wall_time of a 30 ms sleep reported {stats}: not milliseconds")


def _check_gpu_ms(ctx, what: str, frame) -> None:
    for _ in range(2):
        frame()  # warm-up: pipeline creation, first-use allocations
    start = time.perf_counter()
    cpu_ms, gpu_ms = frame()
    wall_ms = (time.perf_counter() - start) * 1e3
    if gpu_ms is None:
        pytest.skip(f"{what}: this adapter has no timestamp queries")
    assert cpu_ms <= wall_ms, f"{what}: CPU time {cpu_ms:.4f} ms exceeds the wall time around it ({wall_ms:.3f} ms)"
    assert gpu_ms <= wall_ms, (f"{what}: the GPU pass took {gpu_ms:.4f} 'ms' by timestamps but the whole frame took "
                               f"{wall_ms:.3f} ms of wall time: the timestamp conversion is not in milliseconds")
    assert gpu_ms >= 1e-3, (f"{what}: the GPU pass took {gpu_ms:.3g} 'ms' by timestamps (wall {wall_ms:.3f} ms): a "
                            "1024x1024 4x MSAA pass takes more than 1 us on any GPU, so this is not milliseconds")
    if "llvmpipe" in ctx.adapter.info["device"]:
        assert gpu_ms >= wall_ms / 10, (f"{what}: on lavapipe the pass is most of the frame's wall time, but the "
                                        f"timestamps say {gpu_ms:.4g} 'ms' of {wall_ms:.3f} ms")


def test_wgpu_pass_timestamps_are_milliseconds(ctx):
    if not ctx.has("timestamp-query"):
        pytest.skip("adapter has no timestamp-query")
    runner = WgpuStageRunner(ctx, "msaa", SIZE)

    def frame():
        """One frame, then its GPU time: the benchmark runners read timestamps deferred (collect_gpu)."""
        cpu_ms, _ = runner.frame()
        return cpu_ms, runner.collect_gpu()[-1]

    _check_gpu_ms(ctx, "wgpu PassTimer", frame)


def test_raw_vulkan_timestamps_are_milliseconds(ctx):
    with RawStageRunner("msaa", SIZE) as runner:
        _check_gpu_ms(ctx, "raw vkCmdWriteTimestamp", runner.frame)


def test_the_raw_runner_reuses_its_target_for_a_transfer_stage_without_validation_errors():
    """The offscreen stage's first barrier starts from TARGET_LAYOUT (raw_path/stages/base.py); the runner's target
    is reused frame after frame (left in TRANSFER_SRC), so the runner moves it there before each frame."""
    with RawStageRunner("offscreen", SIZE) as runner:
        for _ in range(3):
            runner.frame()
        runner.ctx.check_validation("three frames of the raw runner's offscreen stage")
