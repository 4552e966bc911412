"""Frame timing for the report: median frame time and GPU time of a stage or a scene on both paths.

Stages use the benchmark's runners (wgpurender/bench/frames.py). Scenes on wgpu use the
scene benchmark's :class:`~wgpurender.bench.scene.SceneRunner`; on the raw path,
:class:`RawSceneRunner` records the raw path's scene frame (one render pass, two subpasses)
into the same timed frame as a raw stage. A few frames each: the report's numbers are a
quick look on the machine that built it; ``wgpurender bench`` is the measurement.
"""

from __future__ import annotations

import statistics
from dataclasses import dataclass
from pathlib import Path

from ..bench.frames import RawStageRunner, WgpuStageRunner, measure
from ..gpu import GPUContext

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


def scene_wgpu(ctx: GPUContext, path: Path, size: tuple[int, int]) -> Timing:
    from ..bench.scene import SceneRunner
    from ..scene_render import load_renderer
    from ..targets import create_target

    renderer = load_renderer(path, ctx, size=size)
    return _timing(SceneRunner(ctx, renderer, create_target(ctx, renderer.plan.size, renderer.plan.output_format)))


class _SceneAsStage:
    """The raw scene frame behind the interface RawStageRunner records: ``record(cmd, target, t)``."""

    def __init__(self, frame, fmt: str) -> None:
        self.frame, self.format = frame, fmt

    def record(self, cmd, target, t: float) -> None:
        self.frame.record(cmd, target)


class RawSceneRunner(RawStageRunner):
    """RawStageRunner's timed frame (one command buffer, a fence, two timestamps) around a raw scene frame."""

    def __init__(self, path: Path, size: tuple[int, int]) -> None:  # noqa: D107  (replaces the stage set-up)
        from contextlib import ExitStack

        import vulkan as vk

        from ..plan import build_plan
        from ..scene import load_scene
        from ..vulkan_ref.command_buffers import create_command_pool
        from ..vulkan_ref.images import create_image
        from ..vulkan_ref.instance import get_vulkan
        from ..vulkan_ref.scene.frame import SceneFrame
        from ..vulkan_ref.scene.support import check_supported
        from ..vulkan_ref.stages.base import TARGET_USAGE

        scene = load_scene(path)
        plan = build_plan(scene, size=size)
        check_supported(plan)
        self.vk, self.ctx, self.name, self.size, self.t = vk, get_vulkan(), Path(path).stem, plan.size, 0.0
        self.owned = owned = ExitStack()
        ctx = self.ctx
        self.stage = _SceneAsStage(SceneFrame(ctx, owned, scene, plan), plan.output_format)
        self.target = create_image(ctx, owned, self.size, plan.output_format, TARGET_USAGE)
        self.pool = create_command_pool(ctx)
        owned.callback(vk.vkDestroyCommandPool, ctx.device, self.pool, None)
        alloc = vk.VkCommandBufferAllocateInfo(commandPool=self.pool, level=vk.VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                               commandBufferCount=1)
        self.cmd = vk.vkAllocateCommandBuffers(ctx.device, alloc)[0]
        self.fence = vk.vkCreateFence(ctx.device, vk.VkFenceCreateInfo(), None)
        owned.callback(vk.vkDestroyFence, ctx.device, self.fence, None)
        self.queries = vk.vkCreateQueryPool(
            ctx.device, vk.VkQueryPoolCreateInfo(queryType=vk.VK_QUERY_TYPE_TIMESTAMP, queryCount=2), None)
        owned.callback(vk.vkDestroyQueryPool, ctx.device, self.queries, None)
        self.period_ns = float(vk.vkGetPhysicalDeviceProperties(ctx.physical_device).limits.timestampPeriod)
        self._ticks = vk.ffi.new("uint64_t[2]")
        self._readback = None


def scene_raw(path: Path, size: tuple[int, int]) -> Timing:
    with RawSceneRunner(path, size) as runner:
        return _timing(runner)
