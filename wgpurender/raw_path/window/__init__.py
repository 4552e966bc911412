"""A raw-Vulkan window: the C++ tutorial's frame loop, with a stage or a scene of the raw path.

GLFW opens the window (no client API) and makes the VkSurfaceKHR (``glfwCreateWindowSurface``
with the instance extensions GLFW asks for); the queue family must be able to present to it;
the swapchain (swapchain.py) gets the requested present mode, or a UserError naming those offered.

Each frame, the course's synchronisation, each object where it has its natural use:
- **fences** (host <-> GPU): FRAMES_IN_FLIGHT frame slots, each with its own command buffer,
  fence, semaphore, drawable and offscreen image. Before recording into a slot the host waits for
  its fence (the GPU finished the frame that used it last), so the CPU records frame n + 1 while
  the GPU still runs frame n, and never more than FRAMES_IN_FLIGHT ahead. A second wait covers a
  swapchain image still used by another slot's frame (``images_in_flight``).
- **semaphores** (GPU <-> GPU and presentation engine): vkAcquireNextImageKHR signals the slot's
  ``image_available`` semaphore when the image is really free; the submit waits on it at the
  TRANSFER stage only (the stage renders into its own image first, so drawing overlaps the wait),
  and signals the image's ``render_finished`` semaphore, which vkQueuePresentKHR waits on. One
  render_finished per swapchain image: a semaphore must not be signalled again before the
  presentation that waits on it has consumed it.
- **pipeline barriers** (within the command buffer): the swapchain image goes UNDEFINED ->
  TRANSFER_DST (the wait on ``image_available`` chains into this barrier through the TRANSFER
  stage), takes a vkCmdBlitImage of the stage's RGBA image (the swapchain is BGRA on lavapipe: the
  blit swizzles), then -> PRESENT_SRC_KHR; with a screenshot, -> TRANSFER_SRC first for a copy
  into a host buffer (the swapchain is made with TRANSFER_SRC usage for that).
- **subpass dependencies** are inside the stages' and scenes' render passes; **events**
  (vkCmdSetEvent / vkCmdWaitEvents, a split barrier) have no natural use in this loop: nothing
  independent runs between a write and its read.

Resize (GLFW's framebuffer-size callback, or OUT_OF_DATE / SUBOPTIMAL from acquire or present):
wait for the device to idle, re-create the swapchain from the old one, and re-make the slots'
size-dependent objects. Minimised (iconified, or a 0x0 framebuffer): nothing is acquired or
drawn; the loop sleeps in glfwWaitEventsTimeout and re-creates the swapchain on restore.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from contextlib import ExitStack
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import vulkan as vk

from wgpurender.core.course.formats import is_scene_file
from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import save_png
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.core.view import garbage
from wgpurender.core.view.controls import Controls, PausableClock, ScriptEvent, due, install_callbacks, send
from wgpurender.core.view.frame_times import BenchmarkSpec, FrameRecorder, TitleCounter
from wgpurender.core.view.orbit import Orbit, follow, moved_camera
from wgpurender.raw_path.device.checks import check_msaa, check_size
from wgpurender.raw_path.device.context import VulkanContext, create_context
from wgpurender.raw_path.device.images import Image, create_image, subresource_layers, subresource_range
from wgpurender.raw_path.device.memory import HOST_MEMORY, create_buffer, read_host_buffer
from wgpurender.raw_path.stages.base import TARGET_LAYOUT, TARGET_USAGE
from wgpurender.raw_path.window.swapchain import (
    FORMAT_NAMES,
    acquire_next_image,
    check_present_mode,
    create_swapchain,
    destroy_surface,
    destroy_swapchain,
    owned_fence,
    owned_semaphore,
    present,
    presentation_family,
    surface_offer,
)

FRAMES_IN_FLIGHT = 2
NO_TIMEOUT = 0xFFFFFFFFFFFFFFFF
TRANSFER = vk.VK_PIPELINE_STAGE_TRANSFER_BIT
Record = Callable[[object, Image, float], None]  # (command buffer, target, t): what a drawable records


@dataclass
class RawWindowResult:
    frames: int
    mean_frame_ms: float
    last_frame: np.ndarray | None  # RGBA, read back from the presented swapchain image
    offered: str  # what the device offers for the surface
    present_mode: str
    swapchain_format: str
    recreated: int = 0  # swapchain re-creations (resize, out of date, restore)
    events: list[str] = field(default_factory=list)
    benchmark: FrameRecorder | None = None  # --benchmark's frame times (the wgpu window's recorder)
    validation_messages: int | None = None  # with validation on: how many messages the layer sent


def _glfw():
    try:
        import glfw
    except ImportError as err:
        raise UserError(f"cannot import glfw ({err}): pip install glfw, or apt-get install libglfw3") from None
    if not glfw.init():
        raise UserError("GLFW could not open a display: run under a desktop session or Xvfb (DISPLAY must be set)")
    if not glfw.vulkan_supported():
        raise UserError("GLFW finds no Vulkan loader: apt-get install libvulkan1 mesa-vulkan-drivers")
    return glfw


def window_plan(ctx: VulkanContext, scene, size: tuple[int, int] | None, msaa: int | None,
                anisotropy: str = DEFAULT_ANISOTROPY):
    """The plan the window draws a scene with: :func:`wgpurender.core.plan.resolve_plan`'s for this device, as
    the headless paths resolve it, for a swapchain image (not a storage texture, like the wgpu window's)."""
    from wgpurender.core.plan import resolve_plan

    return resolve_plan(scene, ctx.adapter_facts(), size=size, msaa=msaa, anisotropy=anisotropy,
                        output_storage=False)


def drawable_factory(ctx: VulkanContext, target: str, msaa: int | None,
                     anisotropy: str = DEFAULT_ANISOTROPY) -> tuple[Callable, str, object]:
    """(make, format, camera): ``make(owned, size) -> (record, format, drawable)`` makes a raw stage, or a scene
    file drawn by raw_path/scene/, for one size; ``format`` is the colour format it renders; ``camera`` its
    start camera (eye, target, up), None for a flat stage. A scene's plan is
    :func:`wgpurender.core.plan.resolve_plan`'s for this device (``anisotropy``: the per-adapter rule or "scene")."""
    if is_scene_file(target):  # a .toml file or a bundled scene's name, as ``render`` resolves it
        from wgpurender.core.scene import load_scene
        from wgpurender.raw_path.scene.frame import SceneFrame
        from wgpurender.raw_path.scene.support import check_supported

        scene = load_scene(target)

        def make_scene(owned: ExitStack, size: tuple[int, int]):
            plan = window_plan(ctx, scene, size, msaa, anisotropy)
            check_supported(plan)
            frame = SceneFrame(ctx, owned, scene, plan)
            return (lambda cmd, image, t: frame.record(cmd, image)), plan.output_format, frame
        return make_scene, window_plan(ctx, scene, None, msaa, anisotropy).output_format, scene.camera
    from wgpurender.raw_path.stages import get_ref_stage

    cls = get_ref_stage(target)
    samples = check_msaa(ctx, cls, msaa)

    def make_stage(owned: ExitStack, size: tuple[int, int]):
        stage = cls(ctx, owned, cls.default_format, samples, size)
        return stage.record, cls.default_format, stage
    return make_stage, cls.default_format, getattr(cls, "camera", None)


class FrameSlot:
    """One frame in flight: command buffer, fence, image-available semaphore, drawable, its image, readback."""

    def __init__(self, ctx: VulkanContext, owned: ExitStack, pool, make) -> None:
        self.ctx, self.make = ctx, make
        alloc = vk.VkCommandBufferAllocateInfo(commandPool=pool, level=vk.VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                               commandBufferCount=1)
        self.cmd = vk.vkAllocateCommandBuffers(ctx.device, alloc)[0]
        self.fence = owned_fence(ctx, owned, signalled=True)
        self.image_available = owned_semaphore(ctx, owned)
        self.sized = ExitStack()  # the drawable, its target and the readback buffer: re-made on resize
        self.per_frame = ExitStack()  # what one recording makes (framebuffers): freed when the fence says so
        self.size = None

    def resize(self, size: tuple[int, int]) -> None:
        self.per_frame.close()
        self.sized.close()
        self.size = size
        self.record, fmt, self.drawable = self.make(self.sized, size)
        self.target = create_image(self.ctx, self.sized, size, fmt, TARGET_USAGE)
        self.readback = create_buffer(self.ctx, self.sized, size[0] * size[1] * 4, vk.VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      HOST_MEMORY, vk.VK_MEMORY_PROPERTY_HOST_CACHED_BIT)

    def wait(self) -> None:
        """Block until the GPU has finished this slot's previous frame; then its per-frame objects can go."""
        vk.vkWaitForFences(self.ctx.device, 1, [self.fence], vk.VK_TRUE, NO_TIMEOUT)
        self.per_frame.close()

    def close(self) -> None:
        self.per_frame.close()
        self.sized.close()


def image_barrier(cmd, image, old: int, new: int, src: tuple[int, int], dst: tuple[int, int]) -> None:
    """A layout transition of a swapchain image with explicit (stage, access) scopes on both sides."""
    barrier = vk.VkImageMemoryBarrier(
        srcAccessMask=src[1], dstAccessMask=dst[1], oldLayout=old, newLayout=new,
        srcQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED, dstQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED,
        image=image, subresourceRange=subresource_range())
    vk.vkCmdPipelineBarrier(cmd, src[0], dst[0], 0, 0, None, 0, None, 1, [barrier])


class RawWindow:
    """The window, its surface and swapchain, the frame slots, and the frame loop."""

    def __init__(self, glfw, window, ctx: VulkanContext, surface, drawable: tuple[Callable, str],
                 present_mode: str) -> None:
        self.glfw, self.window, self.ctx, self.surface = glfw, window, ctx, surface
        make, self.drawn_format = drawable
        self.offer = surface_offer(ctx, surface)
        self.mode_name = present_mode
        self.present_mode = check_present_mode(self.offer, present_mode)
        self.owned = ExitStack()
        pool = vk.vkCreateCommandPool(ctx.device, vk.VkCommandPoolCreateInfo(
            flags=vk.VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT, queueFamilyIndex=ctx.queue_family), None)
        self.owned.callback(vk.vkDestroyCommandPool, ctx.device, pool, None)
        self.slots = [FrameSlot(ctx, self.owned, pool, make) for _ in range(FRAMES_IN_FLIGHT)]
        self.swapchain = None
        self.swap_owned = ExitStack()  # per-swapchain-image semaphores
        self.resized, self.recreated, self.events = False, 0, []
        glfw.set_framebuffer_size_callback(window, self._on_framebuffer_size)
        self._recreate()

    def _on_framebuffer_size(self, window, width: int, height: int) -> None:
        self.resized = True

    def note(self, event: str) -> None:
        if self.events[-1:] != [event]:
            self.events.append(event)

    def framebuffer_size(self) -> tuple[int, int]:
        return tuple(self.glfw.get_framebuffer_size(self.window))

    def minimised(self) -> bool:
        w, h = self.framebuffer_size()
        return w == 0 or h == 0 or bool(self.glfw.get_window_attrib(self.window, self.glfw.ICONIFIED))

    def _recreate(self) -> None:
        """vkDeviceWaitIdle, a new swapchain from the old one, new per-image semaphores, slots re-sized."""
        vk.vkDeviceWaitIdle(self.ctx.device)
        self.offer = surface_offer(self.ctx, self.surface)  # the current extent follows the window
        old = self.swapchain
        size = check_size(self.ctx, self.offer.current_extent or self.framebuffer_size())
        self.swapchain = create_swapchain(self.ctx, self.surface, self.offer, size, self.present_mode, old,
                                          srgb=self.drawn_format != "rgba8unorm")
        destroy_swapchain(self.ctx, old)
        self.swap_owned.close()
        self.render_finished = [owned_semaphore(self.ctx, self.swap_owned) for _ in self.swapchain.images]
        self.images_in_flight = [None] * len(self.swapchain.images)
        for slot in self.slots:
            if slot.size != self.swapchain.extent:
                slot.resize(self.swapchain.extent)
        if old is not None:
            self.recreated += 1
            self.note(f"swapchain re-created at {size[0]}x{size[1]}")
        self.resized = False

    def frame(self, index: int, t: float, screenshot: bool) -> bool:
        """One frame; False when the swapchain had to be re-created instead (nothing presented)."""
        slot = self.slots[index % FRAMES_IN_FLIGHT]
        slot.wait()
        acquired = vk.ffi.new("uint32_t*")
        try:
            acquire_next_image(self.ctx, self.swapchain, slot.image_available, acquired)
        except vk.VkSuboptimalKhr:  # a success code: the image is acquired and the semaphore will signal
            self.resized = True  # so draw and present it, then re-create
        except vk.VkErrorOutOfDateKhr:  # nothing acquired, the semaphore untouched
            self._recreate()
            return False
        image_index = acquired[0]
        other = self.images_in_flight[image_index]
        if other is not None and other is not slot.fence:
            vk.vkWaitForFences(self.ctx.device, 1, [other], vk.VK_TRUE, NO_TIMEOUT)
        self.images_in_flight[image_index] = slot.fence
        vk.vkResetFences(self.ctx.device, 1, [slot.fence])  # only now: an early return must leave it signalled
        self._record(slot, self.swapchain.images[image_index], t, screenshot)
        submit = vk.VkSubmitInfo(pWaitSemaphores=[slot.image_available], pWaitDstStageMask=[TRANSFER],
                                 pCommandBuffers=[slot.cmd], pSignalSemaphores=[self.render_finished[image_index]])
        vk.vkQueueSubmit(self.ctx.queue, 1, [submit], slot.fence)
        try:
            present(self.ctx, self.swapchain, image_index, self.render_finished[image_index])
        except (vk.VkErrorOutOfDateKhr, vk.VkSuboptimalKhr):
            self.resized = True
        if self.resized:
            self._recreate()
        return True

    def _record(self, slot: FrameSlot, image, t: float, screenshot: bool) -> None:
        cmd = slot.cmd
        vk.vkResetCommandBuffer(cmd, 0)
        vk.vkBeginCommandBuffer(cmd, vk.VkCommandBufferBeginInfo(flags=vk.VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT))
        slot.drawable.owned = slot.per_frame  # this frame's framebuffers are freed after its fence
        # a stage's first barrier starts from TARGET_LAYOUT (stages/base.py); a window frame's target is not zeroed
        image_barrier(cmd, slot.target.handle, vk.VK_IMAGE_LAYOUT_UNDEFINED, TARGET_LAYOUT, (TRANSFER, 0),
                      (TRANSFER, vk.VK_ACCESS_TRANSFER_WRITE_BIT))
        slot.record(cmd, slot.target, t)  # the stage leaves its image in TRANSFER_SRC_OPTIMAL
        layout = vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL
        image_barrier(cmd, image, vk.VK_IMAGE_LAYOUT_UNDEFINED, layout, (TRANSFER, 0),
                      (TRANSFER, vk.VK_ACCESS_TRANSFER_WRITE_BIT))
        w, h = self.swapchain.extent
        corners = [vk.VkOffset3D(x=0, y=0, z=0), vk.VkOffset3D(x=w, y=h, z=1)]
        blit = vk.VkImageBlit(srcSubresource=subresource_layers(), srcOffsets=corners,
                              dstSubresource=subresource_layers(), dstOffsets=corners)
        vk.vkCmdBlitImage(cmd, slot.target.handle, vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image, layout, 1, [blit],
                          vk.VK_FILTER_NEAREST)
        written = (TRANSFER, vk.VK_ACCESS_TRANSFER_WRITE_BIT)
        if screenshot:
            self._record_copy(cmd, slot, image)
            layout, written = vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, (TRANSFER, 0)
        image_barrier(cmd, image, layout, vk.VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, written,
                      (vk.VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0))
        vk.vkEndCommandBuffer(cmd)

    def _record_copy(self, cmd, slot: FrameSlot, image) -> None:
        """The presented image, copied into the slot's host buffer (the screenshot)."""
        src = vk.VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL
        image_barrier(cmd, image, vk.VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, src,
                      (TRANSFER, vk.VK_ACCESS_TRANSFER_WRITE_BIT), (TRANSFER, vk.VK_ACCESS_TRANSFER_READ_BIT))
        w, h = self.swapchain.extent
        region = vk.VkBufferImageCopy(bufferOffset=0, bufferRowLength=0, bufferImageHeight=0,
                                      imageSubresource=subresource_layers(), imageOffset=vk.VkOffset3D(x=0, y=0, z=0),
                                      imageExtent=vk.VkExtent3D(width=w, height=h, depth=1))
        vk.vkCmdCopyImageToBuffer(cmd, image, src, slot.readback.handle, 1, [region])
        barrier = vk.VkBufferMemoryBarrier(
            srcAccessMask=vk.VK_ACCESS_TRANSFER_WRITE_BIT, dstAccessMask=vk.VK_ACCESS_HOST_READ_BIT,
            srcQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED, dstQueueFamilyIndex=vk.VK_QUEUE_FAMILY_IGNORED,
            buffer=slot.readback.handle, offset=0, size=0xFFFFFFFFFFFFFFFF)
        vk.vkCmdPipelineBarrier(cmd, TRANSFER, vk.VK_PIPELINE_STAGE_HOST_BIT, 0, 0, None, 1, [barrier], 0, None)

    def screenshot(self, slot: FrameSlot) -> np.ndarray:
        """The slot's last copy as RGBA uint8 (after its fence): BGRA swapchains swizzled back."""
        slot.wait()
        w, h = slot.size
        pixels = read_host_buffer(self.ctx, slot.readback).view(np.uint8)[: w * h * 4].reshape(h, w, 4)
        name = FORMAT_NAMES.get(self.swapchain.format, "")
        return pixels[..., [2, 1, 0, 3]].copy() if name.startswith("bgra") else pixels.copy()

    def close(self) -> None:
        vk.vkDeviceWaitIdle(self.ctx.device)
        for slot in self.slots:
            slot.close()
        self.swap_owned.close()
        destroy_swapchain(self.ctx, self.swapchain)
        self.owned.close()


def open_window(glfw, title: str, size: tuple[int, int]):
    glfw.window_hint(glfw.CLIENT_API, glfw.NO_API)  # Vulkan draws: GLFW must not make a GL context
    window = glfw.create_window(size[0], size[1], title, None, None)
    if not window:
        raise UserError("GLFW could not create a window")
    return window


def create_window_context(glfw, window) -> tuple[VulkanContext, object]:
    """An instance with GLFW's surface extensions, the surface, and a device with VK_KHR_swapchain whose
    queue family can present to it."""
    made = {}

    def pick_family(instance, physical_device) -> int:
        surface = vk.ffi.new("VkSurfaceKHR*")
        if glfw.create_window_surface(instance, window, None, surface) != vk.VK_SUCCESS:
            raise UserError("glfwCreateWindowSurface failed: the Vulkan driver cannot present to this display")
        made["surface"] = surface[0]
        return presentation_family(instance, physical_device, surface[0])

    extensions = tuple(glfw.get_required_instance_extensions())
    ctx = create_context(extensions, ("VK_KHR_swapchain",), pick_family)
    return ctx, made["surface"]


def run_raw_window(target: str, size: tuple[int, int] = (800, 600), present_mode: str = "fifo",
                   frames: int | None = None, screenshot: bool = False, msaa: int | None = None,
                   fixed_time: float | None = None, on_frame: Callable | None = None,
                   benchmark: BenchmarkSpec | None = None, script: list[ScriptEvent] = (),
                   anisotropy: str = DEFAULT_ANISOTROPY, video=None) -> RawWindowResult:
    """Show a raw stage or scene until the window closes (Esc or the close button), ``frames`` are presented,
    or the benchmark's run time is over.

    The demo's controls are the wgpu window's (core/view/controls.py: orbit camera for scenes and the 3d stage,
    the same keys), as are the FPS title and the benchmark CSV (core/view/frame_times.py). ``screenshot``: the
    last presented frame is copied back from its swapchain image. ``on_frame(glfw, window, n)`` runs before
    frame n (tests use it to resize and minimise); ``script`` is the tests' synthetic input (``demo
    --test-input``). ``anisotropy``: a scene's rule (:func:`drawable_factory`). ``video``: a
    core.files.video.FrameWriter that gets every presented frame (read back from the swapchain image). With
    validation on, any message raises ValidationFailed when the window closes.
    """
    glfw = _glfw()
    title = f"wgpurender --raw: {target}"
    window = open_window(glfw, title, size)
    ctx, surface = create_window_context(glfw, window)
    raw = None
    try:
        make, fmt, camera = drawable_factory(ctx, target, msaa, anisotropy)
        raw = RawWindow(glfw, window, ctx, surface, (make, fmt), present_mode)
        loop = RawDemoLoop(raw, camera, title, benchmark, list(script))
        loop.video = video
        result = loop.run(frames, screenshot, fixed_time, on_frame)
        vk.vkDeviceWaitIdle(ctx.device)
        result.validation_messages = len(ctx.log.messages) if ctx.log is not None else None
        ctx.check_validation(f"the raw-Vulkan window of {target!r}")
        return result
    finally:
        if raw is not None:
            raw.close()
        destroy_surface(ctx, surface)
        ctx.close()
        glfw.destroy_window(window)
        glfw.terminate()


def apply_camera(drawable, orbit: Orbit | None) -> None:
    """Move a raw drawable's camera (a SceneFrame's scene camera, or the 3d stage's) to the orbit's pose."""
    if orbit is None:
        return
    if hasattr(drawable, "scene_subpass"):
        camera = moved_camera(drawable.scene.camera, orbit)
        if camera is not drawable.scene.camera:
            drawable.scene = drawable.scene_subpass.scene = dataclasses.replace(drawable.scene, camera=camera)
    elif getattr(drawable, "camera", None) is not None:
        drawable.camera = moved_camera(drawable.camera, orbit)


class RawDemoLoop:
    """The frame loop of the raw window with the demo's input, title and benchmark (as the wgpu window's)."""

    def __init__(self, raw: RawWindow, camera, title: str, benchmark: BenchmarkSpec | None,
                 script: list[ScriptEvent]) -> None:
        self.raw, self.glfw, self.script = raw, raw.glfw, script
        self.orbit = None if camera is None else Orbit.from_look_at(camera.eye, camera.target, camera.up)
        self._seen = None if camera is None else (tuple(camera.eye), tuple(camera.target), tuple(camera.up))
        self.controls = Controls(self.glfw, lambda: self.orbit)
        install_callbacks(self.glfw, raw.window, self.controls)
        self.titles = TitleCounter(title)
        self.recorder = FrameRecorder(benchmark) if benchmark else None
        self.video = None  # a core.files.video.FrameWriter: every presented frame

    def _due_shots(self, count: int) -> list[Path]:
        shots = []
        for event in due(self.script, count):
            if event.action == "shot":
                shots.append(Path(event.args[0]))
            elif event.action == "wait-reload":
                raise UserError("--test-input wait-reload: the raw window has no live reload")
            elif event.action == "click":
                raise UserError("--test-input click: the raw window has no settings overlay")
            else:
                send(self.controls, event)
        return shots

    def run(self, frames, screenshot: bool, fixed_time, on_frame) -> RawWindowResult:
        raw, glfw = self.raw, self.glfw
        count, times, last_slot = 0, [], None
        settle_at = FRAMES_IN_FLIGHT
        self.controls.clock = PausableClock()
        while not glfw.window_should_close(raw.window) and (frames is None or count < frames):
            if on_frame is not None:
                on_frame(glfw, raw.window, count)
            glfw.poll_events()
            shots = self._due_shots(count)
            if self.controls.close_requested:
                break
            if raw.minimised():
                raw.note("minimised: nothing acquired or drawn")
                glfw.wait_events_timeout(0.05)
                raw.resized = True  # the swapchain is re-created on restore
                continue
            if raw.resized:
                raw._recreate()
                settle_at = count + FRAMES_IN_FLIGHT  # each slot re-makes its drawable in its first frame
            began = time.perf_counter()
            t = fixed_time if fixed_time is not None else self.controls.clock.time()  # P pauses it
            last_wanted = screenshot and (frames is None or count == frames - 1)
            slot = raw.slots[count % FRAMES_IN_FLIGHT]
            if hasattr(slot.drawable, "play"):  # a scene: its glTF animations at this frame's time (stages: none)
                slot.drawable.play(t)  # its re-posed vertices are copied when the slot records, after its fence
                self.orbit, self._seen = follow(self.orbit, self._seen, slot.drawable.scene.camera)
            apply_camera(slot.drawable, self.orbit)
            if not raw.frame(count, t, last_wanted or bool(shots) or self.video is not None):
                continue
            now = time.perf_counter()
            times.append((now - began) * 1000)
            for path in shots:
                save_png(path, raw.screenshot(slot))
            if self.video is not None:
                self.video.write(raw.screenshot(slot))
            last_slot = slot if last_wanted else last_slot
            count += 1
            if count == settle_at:  # every slot has drawn: the load's objects frozen (core/view/garbage.py)
                garbage.settle()
            self._count(now)
            if self.recorder is not None and self.recorder.finished():
                break
        last = raw.screenshot(last_slot) if last_slot is not None else None
        return RawWindowResult(count, float(np.mean(times)) if times else 0.0, last, raw.offer.describe(),
                               raw.mode_name, FORMAT_NAMES.get(raw.swapchain.format, str(raw.swapchain.format)),
                               raw.recreated, raw.events, self.recorder)

    def _count(self, now: float) -> None:
        title = self.titles.frame_done(now)
        if title is not None:
            self.glfw.set_window_title(self.raw.window, title)
        if self.recorder is not None:
            self.recorder.frame_done(now)
