"""A frame of a scene file on the raw path: one render pass, two subpasses, then the readback.

:func:`render_scene_reference` loads the scene, builds the same render plan as the wgpu path
(wgpurender/core/plan/: variants, attachments' formats, the post chain, textures, samplers), refuses
what it cannot draw (support.py), and records everything into one command buffer:
vkCmdBeginRenderPass (clears), subpass 0 (the models), vkCmdNextSubpass, subpass 1 (the post
chain), vkCmdEndRenderPass, vkCmdCopyImageToBuffer.
"""

from __future__ import annotations

import dataclasses
from contextlib import ExitStack
from pathlib import Path

import numpy as np
import vulkan as vk

from wgpurender.core.plan import RenderPlan, gpu_memory, resolve_plan
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.core.scene import Scene
from wgpurender.core.scene.playback import Playback
from wgpurender.raw_path.device.checks import check_size
from wgpurender.raw_path.device.command_buffers import one_shot
from wgpurender.raw_path.device.context import VulkanContext, get_vulkan
from wgpurender.raw_path.device.images import Image, create_image
from wgpurender.raw_path.device.readback import buffer_to_pixels, record_copy_to_buffer
from wgpurender.raw_path.device.renderpass import begin, create_framebuffer
from wgpurender.raw_path.post.chain import PostSubpass
from wgpurender.raw_path.post.neighbourhood import HANDOFF_USAGE, NeighbourhoodPass, split_chain
from wgpurender.raw_path.scene.renderpass import create_scene_render_pass, handoff_format
from wgpurender.raw_path.scene.resources import SceneResources
from wgpurender.raw_path.scene.scene_subpass import SceneSubpass
from wgpurender.raw_path.scene.support import check_supported
from wgpurender.raw_path.stages.base import TARGET_USAGE

TRANSIENT = vk.VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT
USAGES = {  # attachments that live only inside the pass: transient, lazily allocated where offered
    "msaa_color": vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | TRANSIENT,
    "scene_color": vk.VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | vk.VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT | TRANSIENT,
    "depth": vk.VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | TRANSIENT,
    "handoff": HANDOFF_USAGE,  # stored: the next (neighbourhood) pass samples it
}


def set_viewport(cmd, size: tuple[int, int], flip: bool) -> None:
    """The dynamic viewport and scissor over the whole image.

    ``flip`` (scenes in wgpu's y-up convention): y = height, height < 0, as pipeline.set_viewport_and_scissor
    explains. Without it (glm-vulkan scenes): the course's plain viewport; the projection's own Y flip
    (GLM's proj[1][1] *= -1) then turns the image upright, so both give the same pixels and winding.
    """
    width, height = size
    y, h = (float(height), -float(height)) if flip else (0.0, float(height))
    viewport = vk.VkViewport(x=0.0, y=y, width=float(width), height=h, minDepth=0.0, maxDepth=1.0)
    vk.vkCmdSetViewport(cmd, 0, 1, [viewport])
    scissor = vk.VkRect2D(offset=vk.VkOffset2D(x=0, y=0), extent=vk.VkExtent2D(width=width, height=height))
    vk.vkCmdSetScissor(cmd, 0, 1, [scissor])


class SceneFrame:
    """Everything one plan needs on the raw path, made for its size, destroyed with ``owned``."""

    def __init__(self, ctx: VulkanContext, owned: ExitStack, scene: Scene, plan: RenderPlan,
                 wgpu_intermediates: bool = False) -> None:
        self.ctx, self.owned, self.scene, self.plan = ctx, owned, scene, plan
        self.size = plan.size
        head, segments = split_chain(plan.post_steps)  # the effects, however the wgpu path fuses passes
        self.pass_ = create_scene_render_pass(ctx, owned, plan, head, handoff=bool(segments))
        self.images: dict[str, Image] = {
            a.name: create_image(ctx, owned, self.size, a.format, USAGES[a.name], a.samples,
                                 lazy=bool(USAGES[a.name] & TRANSIENT))
            for a in self.pass_.attachments if a.name != "output"
        }
        self.resources = SceneResources(ctx, owned, plan)
        self.scene_subpass = SceneSubpass(ctx, owned, scene, plan, self.resources, self.pass_.render_pass)
        self.post = None
        if self.pass_.has_post:
            self.post = PostSubpass(ctx, owned, plan, self.pass_.render_pass, self.images["scene_color"],
                                    wgpu_intermediates, passes=head)
        self.neighbourhood = self._neighbourhood_passes(segments, wgpu_intermediates)
        self.playback = Playback.of(scene, plan.playing, self.resources.meshes.posed)  # None: a still scene
        self._moved: dict = {}  # re-posed meshes to copy at the start of the next recorded frame

    def play(self, t: float) -> None:
        """Pose the scene's animated glTF models at clock time ``t`` (the window's, once per frame; looped at each
        clip's end: core/scene/playback.py): the file camera and KHR lights placed again now, the re-posed
        vertices copied over their buffers at the start of the next :meth:`record`."""
        if self.playback is None:
            return
        scene, moved = self.playback.frame(t)
        self.scene = self.scene_subpass.scene = dataclasses.replace(self.scene, models=scene.models,
                                                                    lights=scene.lights, camera=scene.camera)
        self._moved.update(moved)

    def _neighbourhood_passes(self, segments, wgpu_intermediates: bool) -> list[tuple[NeighbourhoodPass, Image | None]]:
        """One pass per neighbourhood effect, each with the handoff image it writes (None: the output)."""
        passes, source = [], self.images.get("handoff")
        for i, segment in enumerate(segments):
            final = i == len(segments) - 1
            nb = NeighbourhoodPass(self.ctx, self.owned, self.plan, segment, source, self.plan.output_format, final,
                                   wgpu_intermediates)
            written = None if final else create_image(self.ctx, self.owned, self.size, handoff_format(self.plan),
                                                      HANDOFF_USAGE)
            passes.append((nb, written))
            source = written
        return passes

    def record(self, cmd, target: Image) -> int:
        """Record the frame into ``cmd``; the number of buffer copies of re-posed meshes it starts with."""
        writes = sum(self.resources.rewrite(cmd, key, mesh) for key, mesh in self._moved.items())  # outside the pass
        self._moved = {}
        views = [target if a.name == "output" else self.images[a.name] for a in self.pass_.attachments]
        framebuffer = create_framebuffer(self.ctx, self.owned, self.pass_.render_pass, views)
        begin(cmd, self.pass_.render_pass, framebuffer, self.size)
        set_viewport(cmd, self.size, flip=self.scene.camera.convention != "glm-vulkan")
        self.scene_subpass.record(cmd, self.size)
        if self.post is not None:
            vk.vkCmdNextSubpass(cmd, vk.VK_SUBPASS_CONTENTS_INLINE)
            set_viewport(cmd, self.size, flip=True)  # dynamic state survives the subpass; set for clarity
            self.post.record(cmd, self.size)
        vk.vkCmdEndRenderPass(cmd)
        for nb, written in self.neighbourhood:
            nb.record(cmd, written or target)
        return writes


def render_scene_reference(path: str | Path, size: tuple[int, int] | None = None, fmt: str | None = None,
                           msaa: int | None = None, t: float = 0.0, *, wgpu_intermediates: bool = False,
                           anisotropy: str = DEFAULT_ANISOTROPY) -> np.ndarray:
    """Render a scene file with raw Vulkan calls: (H, W, 4) pixels like wgpurender.render_scene_file's.

    ``size``, ``fmt`` (output format) and ``msaa`` override the scene's [render] table, as on the wgpu
    path; the plan is :func:`wgpurender.core.plan.resolve_plan`'s for this device (``anisotropy``: "scene"
    or "auto", the per-adapter rule). Scenes are static: ``t`` is accepted and ignored.
    ``wgpu_intermediates``: see :func:`render_scene_plan`.
    """
    plan = resolve_plan(path, get_vulkan().adapter_facts(), size=size, output_format=fmt, msaa=msaa,
                        anisotropy=anisotropy)
    return render_scene_plan(plan, t, wgpu_intermediates=wgpu_intermediates)


def render_scene_plan(plan: RenderPlan, t: float = 0.0, *, wgpu_intermediates: bool = False) -> np.ndarray:
    """Render a resolved plan (:func:`wgpurender.core.plan.resolve_plan` for ``get_vulkan().adapter_facts()``)
    with raw Vulkan calls: (H, W, 4) pixels.

    ``wgpu_intermediates`` rounds the post chain's colour to float16 between effects as the wgpu path's
    rgba16float intermediate textures store it (HDR scenes only): the diagnosis of the one difference between
    the paths (tests). UserError for what the raw path cannot draw; with validation on, any message raises.
    """
    check_supported(plan)
    ctx = get_vulkan()
    check_size(ctx, plan.size)
    gpu_memory.check_memory(gpu_memory.plan_textures(plan), ctx.device_type,
                            f"{plan.scene_path.name} at {plan.size[0]}x{plan.size[1]}, msaa {plan.msaa}")
    with ExitStack() as owned:
        frame = SceneFrame(ctx, owned, plan.scene, plan, wgpu_intermediates)
        target = create_image(ctx, owned, plan.size, plan.output_format, TARGET_USAGE)
        with one_shot(ctx) as cmd:
            frame.record(cmd, target)
            buffer = record_copy_to_buffer(ctx, owned, cmd, target)
        pixels = buffer_to_pixels(ctx, buffer, target)
    ctx.check_validation(f"the raw-Vulkan render of {plan.scene_path}")
    return pixels
