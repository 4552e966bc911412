"""Frame timing for the report: median frame time and GPU time of a stage or a scene on both paths.

Stages and scenes use the benchmark's runners (wgpurender/bench/frames.py and bench/scene.py) on
both paths, a few frames each: the report's numbers are a quick look on the machine that built
it; ``wgpurender bench`` is the measurement.
"""

from __future__ import annotations

import statistics
from dataclasses import dataclass
from pathlib import Path

from wgpurender.bench.frames import RawStageRunner, WgpuStageRunner, measure
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.wgpu_path.device.context import GPUContext

FRAMES = 5
WARMUP = 1


@dataclass(frozen=True)
class Timing:
    """Medians in milliseconds; gpu_ms is None without timestamp queries."""

    frame_ms: float
    gpu_ms: float | None


def _timing(runner) -> Timing:
    samples = measure(runner, FRAMES, warmup=WARMUP)
    gpu = statistics.median(samples.gpu) if samples.gpu else None
    return Timing(statistics.median(samples.frame), gpu)


def stage_wgpu(ctx: GPUContext, name: str, size: tuple[int, int]) -> Timing:
    return _timing(WgpuStageRunner(ctx, name, size))


def stage_raw(name: str, size: tuple[int, int]) -> Timing:
    with RawStageRunner(name, size) as runner:
        return _timing(runner)


def scene_wgpu(ctx: GPUContext, path: Path, size: tuple[int, int], anisotropy: str = DEFAULT_ANISOTROPY) -> Timing:
    from wgpurender.bench.scene import SceneRunner

    return _timing(SceneRunner(ctx, path, size, anisotropy))


def scene_raw(path: Path, size: tuple[int, int], anisotropy: str = DEFAULT_ANISOTROPY) -> Timing:
    from wgpurender.bench.scene import RawSceneRunner

    with RawSceneRunner(path, size, anisotropy) as runner:
        return _timing(runner)
