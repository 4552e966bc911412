"""Course concepts: surface, presentation support, swapchain and present modes.

A VkSurfaceKHR is the window as Vulkan sees it (made by GLFW, window.py). What the device can do
with it is asked, not assumed: ``vkGetPhysicalDeviceSurfaceSupportKHR`` (can this queue family
present to it?), ``...SurfaceCapabilitiesKHR`` (image counts, the current extent, usages),
``...SurfaceFormatsKHR`` and ``...SurfacePresentModesKHR``. A VkSwapchainKHR is then a ring of
images the presentation engine owns and lends out: ``vkAcquireNextImageKHR`` hands one over
(signalling a semaphore when it is really free), ``vkQueuePresentKHR`` gives it back (waiting on a
semaphore for the rendering). A resize makes it out of date: it is re-created, passing the old one
as ``oldSwapchain``.

Present modes (the course's list): FIFO waits for the vertical blank, a queue of images (always
offered, the only one every device must have); MAILBOX also waits, but a new image replaces the
waiting one (no tearing, lowest latency); IMMEDIATE presents at once (may tear).

The surface and swapchain functions are extension functions: the ``vulkan`` binding reaches them
through vkGetInstanceProcAddr / vkGetDeviceProcAddr, as a C program does.
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass

import vulkan as vk

from wgpurender.core.errors import UserError
from wgpurender.raw_path.device.context import VulkanContext

PRESENT_MODES = {
    "immediate": vk.VK_PRESENT_MODE_IMMEDIATE_KHR,
    "mailbox": vk.VK_PRESENT_MODE_MAILBOX_KHR,
    "fifo": vk.VK_PRESENT_MODE_FIFO_KHR,
    "fifo-relaxed": vk.VK_PRESENT_MODE_FIFO_RELAXED_KHR,
}
MODE_NAMES = {value: name for name, value in PRESENT_MODES.items()}
# the stage's RGBA image is blitted in (TRANSFER_DST), a screenshot copies it out (TRANSFER_SRC)
IMAGE_USAGE = vk.VK_IMAGE_USAGE_TRANSFER_DST_BIT | vk.VK_IMAGE_USAGE_TRANSFER_SRC_BIT
# preferred surface formats: sRGB first, as the offscreen stages render rgba8unorm-srgb
FORMAT_NAMES = {
    vk.VK_FORMAT_B8G8R8A8_SRGB: "bgra8unorm-srgb", vk.VK_FORMAT_R8G8B8A8_SRGB: "rgba8unorm-srgb",
    vk.VK_FORMAT_B8G8R8A8_UNORM: "bgra8unorm", vk.VK_FORMAT_R8G8B8A8_UNORM: "rgba8unorm",
}


def presentation_family(instance, physical_device, surface) -> int:
    """The first queue family that does graphics and can present to ``surface`` (often the same one)."""
    supports = vk.vkGetInstanceProcAddr(instance, "vkGetPhysicalDeviceSurfaceSupportKHR")
    for index, family in enumerate(vk.vkGetPhysicalDeviceQueueFamilyProperties(physical_device)):
        if family.queueFlags & vk.VK_QUEUE_GRAPHICS_BIT and supports(physical_device, index, surface):
            return index
    raise UserError("no queue family of the Vulkan device can both draw and present to this window")


@dataclass(frozen=True)
class SurfaceOffer:
    """What the device offers for the surface: present modes and formats by name, and the capabilities."""

    present_modes: tuple[str, ...]
    formats: tuple[int, ...]  # VkFormat, in the driver's order
    min_images: int
    max_images: int  # 0: no limit
    current_extent: tuple[int, int] | None  # None: the window decides (0xFFFFFFFF)
    transform: int
    composite_alpha: int

    def describe(self) -> str:
        names = [FORMAT_NAMES.get(f, str(f)) for f in self.formats]
        images = f"{self.min_images}..{self.max_images or 'any'}"
        return f"present modes {', '.join(self.present_modes)}; formats {', '.join(names)}; images {images}"


def surface_offer(ctx: VulkanContext, surface) -> SurfaceOffer:
    pd = ctx.physical_device
    caps = vk.vkGetInstanceProcAddr(ctx.instance, "vkGetPhysicalDeviceSurfaceCapabilitiesKHR")(pd, surface)
    modes = vk.vkGetInstanceProcAddr(ctx.instance, "vkGetPhysicalDeviceSurfacePresentModesKHR")(pd, surface)
    formats = vk.vkGetInstanceProcAddr(ctx.instance, "vkGetPhysicalDeviceSurfaceFormatsKHR")(pd, surface)
    extent = caps.currentExtent
    alpha = caps.supportedCompositeAlpha
    opaque = vk.VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
    return SurfaceOffer(
        present_modes=tuple(MODE_NAMES.get(m, str(m)) for m in modes),
        formats=tuple(f.format for f in formats if f.colorSpace == vk.VK_COLOR_SPACE_SRGB_NONLINEAR_KHR),
        min_images=caps.minImageCount, max_images=caps.maxImageCount,
        current_extent=None if extent.width == 0xFFFFFFFF else (extent.width, extent.height),
        transform=caps.currentTransform, composite_alpha=opaque if alpha & opaque else alpha & -alpha,
    )


def choose_format(offer: SurfaceOffer, srgb: bool = True) -> int:
    """An sRGB format (the drawable renders rgba8unorm-srgb or float), or a UNORM one (it renders rgba8unorm,
    already encoded by its shader), so that the blit copies the encoded bytes as they are; else the first."""
    srgb_formats = (vk.VK_FORMAT_B8G8R8A8_SRGB, vk.VK_FORMAT_R8G8B8A8_SRGB)
    unorm_formats = (vk.VK_FORMAT_B8G8R8A8_UNORM, vk.VK_FORMAT_R8G8B8A8_UNORM)
    for fmt in srgb_formats if srgb else unorm_formats:
        if fmt in offer.formats:
            return fmt
    if not offer.formats:
        raise UserError("the window surface offers no sRGB-nonlinear colour format")
    return offer.formats[0]


def check_present_mode(offer: SurfaceOffer, name: str) -> int:
    if name not in offer.present_modes:
        raise UserError(f"present mode {name!r} is not offered by this device and window: "
                        f"it offers {', '.join(offer.present_modes)}")
    return PRESENT_MODES[name]


@dataclass
class Swapchain:
    handle: object
    images: list  # VkImage handles, owned by the swapchain (never destroyed by us)
    format: int
    extent: tuple[int, int]


def create_swapchain(ctx: VulkanContext, surface, offer: SurfaceOffer, window_size: tuple[int, int],
                     present_mode: int, old: Swapchain | None = None, srgb: bool = True) -> Swapchain:
    """vkCreateSwapchainKHR: one image more than the minimum (so acquiring rarely waits), the surface's
    extent (or the window's, clamped, where the surface leaves it to us), exclusive to one queue family."""
    fmt = choose_format(offer, srgb)
    extent = offer.current_extent or window_size
    count = offer.min_images + 1 if not offer.max_images else min(offer.min_images + 1, offer.max_images)
    info = vk.VkSwapchainCreateInfoKHR(
        surface=surface, minImageCount=count, imageFormat=fmt, imageColorSpace=vk.VK_COLOR_SPACE_SRGB_NONLINEAR_KHR,
        imageExtent=vk.VkExtent2D(width=extent[0], height=extent[1]), imageArrayLayers=1, imageUsage=IMAGE_USAGE,
        imageSharingMode=vk.VK_SHARING_MODE_EXCLUSIVE, preTransform=offer.transform,
        compositeAlpha=offer.composite_alpha, presentMode=present_mode, clipped=vk.VK_TRUE,
        oldSwapchain=old.handle if old is not None else vk.VK_NULL_HANDLE,
    )
    handle = vk.vkGetDeviceProcAddr(ctx.device, "vkCreateSwapchainKHR")(ctx.device, info, None)
    images = list(vk.vkGetDeviceProcAddr(ctx.device, "vkGetSwapchainImagesKHR")(ctx.device, handle))
    return Swapchain(handle, images, fmt, tuple(extent))


def acquire_next_image(ctx: VulkanContext, swapchain: Swapchain, semaphore, index) -> None:
    """vkAcquireNextImageKHR into ``index`` (a uint32_t*), signalling ``semaphore`` when the image is free.

    The index pointer is ours: the binding raises VkSuboptimalKhr for that success code, and without our
    pointer the acquired image's index would be lost with the exception.
    """
    acquire = vk.vkGetDeviceProcAddr(ctx.device, "vkAcquireNextImageKHR")
    acquire(ctx.device, swapchain.handle, 0xFFFFFFFFFFFFFFFF, semaphore, vk.VK_NULL_HANDLE, index)


def present(ctx: VulkanContext, swapchain: Swapchain, image_index: int, wait_semaphore) -> None:
    """vkQueuePresentKHR: give the image back to the presentation engine once ``wait_semaphore`` signals."""
    info = vk.VkPresentInfoKHR(pWaitSemaphores=[wait_semaphore], pSwapchains=[swapchain.handle],
                               pImageIndices=[image_index])
    vk.vkGetDeviceProcAddr(ctx.device, "vkQueuePresentKHR")(ctx.queue, info)


def destroy_swapchain(ctx: VulkanContext, swapchain: Swapchain | None) -> None:
    if swapchain is not None:
        vk.vkGetDeviceProcAddr(ctx.device, "vkDestroySwapchainKHR")(ctx.device, swapchain.handle, None)


def destroy_surface(ctx: VulkanContext, surface) -> None:
    vk.vkGetInstanceProcAddr(ctx.instance, "vkDestroySurfaceKHR")(ctx.instance, surface, None)


def owned_semaphore(ctx: VulkanContext, owned: ExitStack):
    """A binary semaphore: GPU-to-GPU (and GPU-to-presentation-engine) ordering; the host never waits on it."""
    semaphore = vk.vkCreateSemaphore(ctx.device, vk.VkSemaphoreCreateInfo(), None)
    owned.callback(vk.vkDestroySemaphore, ctx.device, semaphore, None)
    return semaphore


def owned_fence(ctx: VulkanContext, owned: ExitStack, signalled: bool = True):
    """A fence: the GPU signals it when a submission finishes, the host waits on it. Made signalled, so
    that waiting for a frame slot's previous frame returns at once the first time round."""
    flags = vk.VK_FENCE_CREATE_SIGNALED_BIT if signalled else 0
    fence = vk.vkCreateFence(ctx.device, vk.VkFenceCreateInfo(flags=flags), None)
    owned.callback(vk.vkDestroyFence, ctx.device, fence, None)
    return fence
