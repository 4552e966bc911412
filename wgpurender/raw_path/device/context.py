"""Course concepts: instance, physical device, queue family, logical device.

The chain every Vulkan program starts with: a VkInstance (with the validation layer
when asked for), a VkPhysicalDevice chosen from those the instance enumerates, a
queue family on it that can do graphics (graphics families can always transfer),
and a VkDevice with one queue from that family. Headless: no surface and no
swapchain, so no presentation support is needed from the family.
"""

from __future__ import annotations

import atexit
import functools
from dataclasses import dataclass, field

import vulkan as vk

from wgpurender.core.errors import UserError
from wgpurender.core.plan import AdapterFacts
from wgpurender.raw_path.device import validation
from wgpurender.raw_path.device.pipeline_cache import create_pipeline_cache, save_pipeline_cache

DEVICE_TYPES = {  # VkPhysicalDeviceType -> the adapter type wgpu reports for it
    vk.VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: "DiscreteGPU",
    vk.VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: "IntegratedGPU",
    vk.VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: "VirtualGPU",
    vk.VK_PHYSICAL_DEVICE_TYPE_CPU: "CPU",
}
API_VERSION = vk.VK_MAKE_VERSION(1, 1, 0)  # 1.1: negative viewport heights (VK_KHR_maintenance1) are core


@dataclass(frozen=True)
class MemoryType:
    flags: int  # VkMemoryPropertyFlags
    heap: int  # index into heaps


@dataclass(frozen=True)
class Limits:
    """The VkPhysicalDeviceLimits we use, copied out: the binding's structs point into memory that is freed."""

    max_image_dimension_2d: int
    framebuffer_color_sample_counts: int
    min_uniform_buffer_offset_alignment: int
    max_push_constants_size: int
    max_storage_buffer_range: int = 1 << 27  # the spec's least maximum (128 MiB)


@dataclass
class VulkanContext:
    instance: object
    physical_device: object
    device: object
    queue: object
    queue_family: int
    device_name: str
    memory_types: list[MemoryType]
    heap_sizes: list[int]
    limits: Limits
    log: validation.MessageLog | None = None
    messenger: object = None
    pipeline_cache: object = None
    pipeline_cache_file: object = None
    pipeline_cache_key: str = ""  # what the saved cache data depends on (pipeline_cache.py)
    device_type: str = ""  # as wgpu names adapter types: "DiscreteGPU", "IntegratedGPU", "CPU", ... (DEVICE_TYPES)
    _closed: bool = field(default=False, repr=False)

    def check_validation(self, what: str) -> None:
        """Raise ValidationFailed if the validation layer said anything since the last check."""
        if self.log is not None:
            self.log.raise_if_any(what)

    def describe(self) -> str:
        return f"{self.device_name} (raw Vulkan, validation {'on' if self.log else 'off'})"

    def adapter_facts(self) -> AdapterFacts:
        """What the plan's "auto" knobs need to know about this device (:func:`wgpurender.core.plan.resolve_plan`):
        the same facts the wgpu path reports for the same device. Push constants (immediates) are core Vulkan, and
        so is drawIndirectFirstInstance (the culling plan's feature; lavapipe and NVIDIA have it)."""
        return AdapterFacts.of(self.device_type, ("immediates", "indirect-first-instance"), self.device_name, "Vulkan",
                               {"max-storage-buffer-binding-size": self.limits.max_storage_buffer_range})

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        vk.vkDeviceWaitIdle(self.device)
        if self.pipeline_cache is not None:
            save_pipeline_cache(self)
            vk.vkDestroyPipelineCache(self.device, self.pipeline_cache, None)
        vk.vkDestroyDevice(self.device, None)
        if self.messenger is not None:
            validation.destroy_messenger(self.instance, self.messenger)
        vk.vkDestroyInstance(self.instance, None)


def create_instance(log: validation.MessageLog | None, extensions: tuple[str, ...] = ()):
    """vkCreateInstance: application info, layers, extensions; with validation, a pNext chain.

    The messenger create-info also goes on the chain, so that messages from
    vkCreateInstance itself are caught before the real messenger exists.
    """
    app = vk.VkApplicationInfo(
        pApplicationName="wgpurender-vulkan-ref", applicationVersion=1, pEngineName="wgpurender",
        engineVersion=1, apiVersion=API_VERSION,
    )
    layers, extensions, chain = [], list(extensions), []
    if log is not None:
        validation.check_layer_available()
        layers = [validation.LAYER]
        extensions += ["VK_EXT_debug_utils", "VK_EXT_validation_features"]
        messenger = validation.messenger_info(log)
        features = validation.validation_features()
        features.pNext = vk.ffi.addressof(messenger)
        chain = [messenger, features]  # keep both alive until vkCreateInstance returns
    info = vk.VkInstanceCreateInfo(
        pApplicationInfo=app,
        ppEnabledLayerNames=layers,
        ppEnabledExtensionNames=extensions,
        pNext=chain[-1] if chain else None,
    )
    try:
        return vk.vkCreateInstance(info, None)
    except vk.VkError as err:
        raise UserError(f"cannot create a Vulkan instance ({type(err).__name__}): install a Vulkan driver "
                        "(apt install mesa-vulkan-drivers for lavapipe)") from None


def pick_physical_device(instance):
    """Prefer a discrete GPU, then an integrated one, then anything (lavapipe is a CPU device)."""
    devices = list(vk.vkEnumeratePhysicalDevices(instance))
    if not devices:
        raise UserError("no Vulkan physical device found (apt install mesa-vulkan-drivers for lavapipe)")
    rank = {
        vk.VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: 0,
        vk.VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: 1,
        vk.VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: 2,
        vk.VK_PHYSICAL_DEVICE_TYPE_CPU: 3,
    }
    usable = [d for d in devices if vk.vkGetPhysicalDeviceProperties(d).apiVersion >= API_VERSION]
    if not usable:
        raise UserError("no Vulkan 1.1 device found: the reference path needs Vulkan 1.1")
    return min(usable, key=lambda d: rank.get(vk.vkGetPhysicalDeviceProperties(d).deviceType, 9))


def find_queue_family(physical_device) -> int:
    """The first queue family with VK_QUEUE_GRAPHICS_BIT (it also does transfers)."""
    for index, family in enumerate(vk.vkGetPhysicalDeviceQueueFamilyProperties(physical_device)):
        if family.queueCount > 0 and family.queueFlags & vk.VK_QUEUE_GRAPHICS_BIT:
            return index
    raise UserError("the Vulkan device has no graphics queue family")


def create_device(physical_device, family: int, extensions: tuple[str, ...] = ()):
    """vkCreateDevice with one queue of ``family`` and ``extensions`` (none headless; VK_KHR_swapchain for
    the window, raw_path/window/__init__.py); one optional feature,
    samplerAnisotropy, when the device offers it (anisotropic samplers need it; wgpu enables it the same way)."""
    queue_info = vk.VkDeviceQueueCreateInfo(queueFamilyIndex=family, queueCount=1, pQueuePriorities=[1.0])
    offered = vk.vkGetPhysicalDeviceFeatures(physical_device)
    features = vk.VkPhysicalDeviceFeatures(samplerAnisotropy=offered.samplerAnisotropy)
    info = vk.VkDeviceCreateInfo(pQueueCreateInfos=[queue_info], pEnabledFeatures=features,
                                 ppEnabledExtensionNames=list(extensions))
    device = vk.vkCreateDevice(physical_device, info, None)
    return device, vk.vkGetDeviceQueue(device, family, 0)


def memory_types(physical_device) -> tuple[list[MemoryType], list[int]]:
    """The device's memory types (property flags + heap) and heap sizes, from vkGetPhysicalDeviceMemoryProperties."""
    props = vk.vkGetPhysicalDeviceMemoryProperties(physical_device)
    types = [MemoryType(props.memoryTypes[i].propertyFlags, props.memoryTypes[i].heapIndex)
             for i in range(props.memoryTypeCount)]
    return types, [props.memoryHeaps[i].size for i in range(props.memoryHeapCount)]


def copy_limits(limits) -> Limits:
    return Limits(
        max_image_dimension_2d=limits.maxImageDimension2D,
        framebuffer_color_sample_counts=limits.framebufferColorSampleCounts,
        min_uniform_buffer_offset_alignment=limits.minUniformBufferOffsetAlignment,
        max_push_constants_size=limits.maxPushConstantsSize,
        max_storage_buffer_range=limits.maxStorageBufferRange,
    )


@functools.cache
def _process_log() -> validation.MessageLog:
    """One message log for every context of the process: the binding has one global callback slot, so a
    second context's messenger (the window's) would otherwise take the first one's messages away."""
    return validation.MessageLog()


@functools.cache
def get_vulkan() -> VulkanContext:
    """The process-wide raw Vulkan context (validation per $WGPURENDER_VALIDATION when first called)."""
    return create_context()


def create_context(instance_extensions: tuple[str, ...] = (), device_extensions: tuple[str, ...] = (),
                   pick_family=None) -> VulkanContext:
    """A new context: headless by default. The window (window.py) asks for the surface and swapchain
    extensions, and picks a queue family that can also present: ``pick_family(instance, physical_device)
    -> index``, called once the instance exists (the surface it checks is made from the instance)."""
    from wgpurender.core.files.runtime_dir import ensure_runtime_dir

    ensure_runtime_dir()  # before the instance: no "XDG_RUNTIME_DIR is invalid" lines from the driver
    log = _process_log() if validation.validation_requested() else None
    instance = create_instance(log, instance_extensions)
    messenger = validation.create_messenger(instance, log) if log is not None else None
    physical = pick_physical_device(instance)
    family = pick_family(instance, physical) if pick_family else find_queue_family(physical)
    device, queue = create_device(physical, family, device_extensions)
    props = vk.vkGetPhysicalDeviceProperties(physical)
    types, heaps = memory_types(physical)
    ctx = VulkanContext(
        instance=instance, physical_device=physical, device=device, queue=queue, queue_family=family,
        device_name=props.deviceName, memory_types=types, heap_sizes=heaps, limits=copy_limits(props.limits),
        log=log, messenger=messenger, device_type=DEVICE_TYPES.get(props.deviceType, "Other"),
    )
    ctx.pipeline_cache = create_pipeline_cache(ctx, props)
    atexit.register(ctx.close)
    ctx.check_validation("device creation")
    return ctx
