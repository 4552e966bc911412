"""The Vulkan -> wgpu mapping table: one row per course concept, with where each side lives in this repository.

Every row names the raw-Vulkan calls, the functions of the raw reference path
(wgpurender/raw_path/) that make them, the wgpu API that stands for them, the
functions of the wgpu path that use it, and what differs. Code locations are
``"module:attribute.path"`` strings (``Class.method`` allowed); tests/test_concepts.py
imports every one, so a rename cannot leave the table pointing at nothing.

docs/vulkan-mapping.md is generated from :data:`CONCEPTS`::

    python -m wgpurender.concepts > docs/vulkan-mapping.md     # or: wgpurender concepts --markdown

and the test fails when the committed file differs from a fresh generation.
"""

from __future__ import annotations

import importlib
import sys
import textwrap
from dataclasses import dataclass

R = "wgpurender.raw_path."
W = "wgpurender.wgpu_path."
C = "wgpurender."  # core locations are written "core.module:attr"


@dataclass(frozen=True)
class Concept:
    """One row. ``raw_note`` says why ``raw`` is empty, where it is. ``demonstrated`` False: a course concept
    that neither path has code for (the row says why), shown as "not demonstrated"."""

    name: str
    vulkan: tuple[str, ...]
    raw: tuple[str, ...]
    wgpu: tuple[str, ...]
    wgpu_where: tuple[str, ...]
    differs: str
    raw_note: str = ""
    demonstrated: bool = True


def _raw(*locations: str) -> tuple[str, ...]:
    return tuple(R + loc for loc in locations)


def _wgpu(*locations: str) -> tuple[str, ...]:
    """wgpu-path locations; ``core.`` ones are the API-free code the wgpu path builds on (WGSL structs, variants)."""
    return tuple((C if loc.startswith("core.") else W) + loc for loc in locations)


CONCEPTS: list[Concept] = [
    Concept(
        "instance",
        ("vkCreateInstance", "VkApplicationInfo", "ppEnabledLayerNames / ppEnabledExtensionNames",
         "vkCreateDebugUtilsMessengerEXT"),
        _raw("device.context:create_instance", "device.validation:create_messenger",
             "device.validation:validation_features"),
        ("wgpu.gpu (created on first use)", "set_instance_extras(backends=[...], flags=['Validation'])"),
        _wgpu("device.context:_configure_instance_once", "device.context:_enumerate"),
        "wgpu-py creates the instance itself on first use: no application info, no layer or extension lists. "
        "The validation layer is one instance flag, and its messages arrive on the Python 'wgpu' logger instead "
        "of a debug messenger callback (tests/conftest.py collects them).",
    ),
    Concept(
        "physical device",
        ("vkEnumeratePhysicalDevices", "vkGetPhysicalDeviceProperties (deviceType, apiVersion, limits)",
         "vkGetPhysicalDeviceFeatures"),
        _raw("device.context:pick_physical_device", "device.context:copy_limits", "device.context:create_device"),
        ("wgpu.gpu.enumerate_adapters_sync", "GPUAdapter.info / .features / .limits"),
        _wgpu("device.context:select_adapter", "device.context:available_backends"),
        "An adapter is a physical device seen through one backend (Vulkan, Metal, D3D12, GL). Its features and "
        "limits are WebGPU's portable names (max-texture-dimension-2d), not VkPhysicalDeviceLimits fields; "
        "adapter_type ranks like deviceType.",
    ),
    Concept(
        "queue families",
        ("vkGetPhysicalDeviceQueueFamilyProperties", "VK_QUEUE_GRAPHICS_BIT", "vkGetDeviceQueue"),
        _raw("device.context:find_queue_family", "device.context:create_device"),
        ("GPUDevice.queue",),
        _wgpu("device.context:GPUContext.queue"),
        "No queue families: wgpu picks a family that does graphics, compute and transfer and gives the device "
        "exactly one queue. No transfer-only or async-compute queues, so no queue family ownership transfers.",
    ),
    Concept(
        "device",
        ("vkCreateDevice", "VkDeviceQueueCreateInfo", "VkPhysicalDeviceFeatures (pEnabledFeatures)"),
        _raw("device.context:create_device", "device.context:get_vulkan"),
        ("GPUAdapter.request_device_sync(required_features=, required_limits=)",),
        _wgpu("device.context:_build_context", "device.context:OPTIONAL_FEATURES"),
        "Features are requested by WebGPU name ('timestamp-query', 'immediates'), limits by name; there are no "
        "device extensions to list. Core capabilities such as sampler anisotropy need no request: wgpu turns on "
        "the Vulkan feature itself when the adapter has it.",
    ),
    Concept(
        "surface",
        ("glfwCreateWindowSurface (GLFW makes the platform's surface: Xlib or XCB, Wayland, Win32)",
         "vkGetPhysicalDeviceSurfaceSupportKHR", "vkGetPhysicalDeviceSurfaceFormatsKHR",
         "vkGetPhysicalDeviceSurfaceCapabilitiesKHR", "vkDestroySurfaceKHR"),
        _raw("window:create_window_context", "window.swapchain:presentation_family", "window.swapchain:surface_offer",
             "window.swapchain:destroy_surface"),
        ("wgpu.utils.get_glfw_present_info(window)", "wgpu.gpu.get_canvas_context(present_info)",
         "GPUCanvasContext.get_preferred_format"),
        _wgpu("window:present_info", "window:surface_format", "window:DemoWindow.__init__"),
        "One canvas context per window, made from the native window handles; it is surface and swapchain in one "
        "object. wgpu checks that the queue can present, so there is no present-support query. The raw window "
        "(wgpurender demo --raw) asks GLFW for the surface (glfwCreateWindowSurface, with the instance extensions "
        "GLFW names: VK_KHR_surface + VK_KHR_xcb_surface under X11) and picks a queue family that can present.",
    ),
    Concept(
        "presentation and present modes",
        ("vkQueuePresentKHR", "VkPresentModeKHR (FIFO, MAILBOX, IMMEDIATE)", "VkSwapchainCreateInfoKHR.presentMode",
         "vkGetPhysicalDeviceSurfacePresentModesKHR"),
        _raw("window.swapchain:surface_offer", "window.swapchain:create_swapchain", "window.swapchain:present"),
        ("GPUCanvasContext.present()", "get_glfw_present_info(window, vsync=True / False)"),
        _wgpu("window:present_info", "window:PRESENT_MODES", "window:DemoWindow.frame"),
        "Present modes are chosen through the canvas context: wgpu-py 0.32 only exposes vsync on/off, so fifo "
        "is vsync on and immediate is vsync off (wgpu falls back to mailbox, then fifo); mailbox cannot be asked "
        "for. There is no separate present queue and no wait semaphore to pass. The raw window presents with "
        "vkQueuePresentKHR waiting on the image's render-finished semaphore, and prints what the surface offers "
        "(lavapipe under Xvfb: immediate, mailbox, fifo, fifo-relaxed).",
    ),
    Concept(
        "heaps and memory types",
        ("vkGetPhysicalDeviceMemoryProperties", "VkMemoryRequirements.memoryTypeBits", "vkAllocateMemory",
         "vkBindBufferMemory / vkBindImageMemory"),
        _raw("device.context:memory_types", "device.memory:find_memory_type", "device.memory:allocate",
             "device.memory:create_buffer",
             "device.images:create_image"),
        ("device.create_buffer(usage=)", "device.create_texture(usage=)", "BufferUsage.MAP_READ / MAP_WRITE"),
        _wgpu("device.targets:create_target", "device.targets:read_texture"),
        "No heaps or memory types are visible: wgpu allocates (and sub-allocates) memory for each resource and "
        "picks the type from the usage flags; MAP_READ / MAP_WRITE buffers land in host-visible memory. There is "
        "no LAZILY_ALLOCATED choice for transient attachments.",
    ),
    Concept(
        "staging",
        ("staging VkBuffer in HOST_VISIBLE | HOST_COHERENT memory", "vkMapMemory / vkUnmapMemory",
         "vkCmdCopyBuffer", "vkCmdCopyBufferToImage"),
        _raw("device.memory:upload_buffer", "device.memory:record_copy", "device.memory:write_host_buffer",
             "device.textures:upload_texture", "device.textures:record_upload"),
        ("queue.write_buffer", "queue.write_texture", "device.create_buffer_with_data"),
        _wgpu("stages.triangle_buffers:TriangleBuffers.setup", "device.textures:upload_level",
              "stages.cube3d:Cube3D.record"),
        "wgpu stages the bytes in its own upload buffer, records the copy before the next submit and inserts the "
        "barrier after it. write_texture has no 256-byte row alignment (copy_buffer_to_texture has).",
    ),
    Concept(
        "command pool and buffers",
        ("vkCreateCommandPool", "vkAllocateCommandBuffers", "vkBeginCommandBuffer / vkEndCommandBuffer",
         "vkQueueSubmit"),
        _raw("device.command_buffers:create_command_pool", "device.command_buffers:one_shot",
             "device.command_buffers:submit_and_wait"),
        ("device.create_command_encoder", "GPUCommandEncoder.finish() -> GPUCommandBuffer", "queue.submit"),
        _wgpu("render:render_stage", "device.frame_loop:run_frame"),
        "No pools and no reset: an encoder records once and finish() gives a single-use command buffer. No "
        "secondary command buffers (render bundles come closest). The states initial -> recording -> "
        "executable -> pending are the encoder's life, unnamed.",
    ),
    Concept(
        "descriptor pool",
        ("vkCreateDescriptorPool", "VkDescriptorPoolSize", "maxSets"),
        _raw("device.descriptors:create_pool"),
        ("(none: device.create_bind_group allocates)",),
        _wgpu("device.bind_groups:uniform_group"),
        "wgpu manages descriptor pools itself: no pool sizes to count, no pool exhaustion, and a bind group's "
        "descriptors are freed when it is dropped.",
    ),
    Concept(
        "set layouts",
        ("VkDescriptorSetLayoutBinding", "vkCreateDescriptorSetLayout"),
        _raw("device.descriptors:binding", "device.descriptors:create_set_layout",
             "stages.textured:Textured._setup_descriptors"),
        ("device.create_bind_group_layout(entries=)", "GPURenderPipeline.get_bind_group_layout (layout 'auto')"),
        _wgpu("device.bind_groups:uniform_layout", "stages.textured:TexturedPipelines.__init__",
              "post.passes:PlannedPass._entries"),
        "An entry says more than a descriptor type: a texture's sample type (filterable float or not) and a "
        "buffer's min_binding_size and has_dynamic_offset. No combined image sampler type, no immutable "
        "samplers, no descriptor arrays (descriptorCount > 1) without native features.",
    ),
    Concept(
        "sets and updates",
        ("vkAllocateDescriptorSets", "VkWriteDescriptorSet + vkUpdateDescriptorSets",
         "vkCmdBindDescriptorSets (dynamic offsets)"),
        _raw("device.descriptors:allocate_sets", "device.descriptors:write_buffer", "device.descriptors:write_image",
             "device.descriptors:update", "stages.cube3d:Cube3D._setup_descriptors", "stages.cube3d:Cube3D.record",
             "stages.textured:Textured._setup_descriptors", "stages.textured:Textured.record"),
        ("device.create_bind_group(layout=, entries=)", "GPURenderPassEncoder.set_bind_group(index, group, offsets)"),
        _wgpu("device.bind_groups:uniform_group", "stages.cube3d:Cube3D.record",
              "stages.textured:TexturedPipelines.group"),
        "Allocation and writes are one call, and a bind group is immutable: to point at other resources, make a "
        "new one. Dynamic offsets work the same way (one group, one offset per draw).",
    ),
    Concept(
        "images",
        ("vkCreateImage", "VkImageCreateInfo (format, extent, mipLevels, samples, tiling, usage)"),
        _raw("device.images:create_image", "device.images:FORMATS", "device.textures:create_texture_image"),
        ("device.create_texture(size=, format=, usage=, mip_level_count=, sample_count=)",),
        _wgpu("device.targets:create_target", "device.textures:create_texture"),
        "Memory comes with the texture, tiling is always optimal and the initial layout is not given. Usage "
        "names differ: RENDER_ATTACHMENT, TEXTURE_BINDING, COPY_SRC / COPY_DST.",
    ),
    Concept(
        "views",
        ("vkCreateImageView", "VkImageViewCreateInfo (viewType, format, components)"),
        _raw("device.images:create_view", "device.textures:TextureImage.level"),
        ("GPUTexture.create_view(format=, dimension=, base_mip_level=, mip_level_count=, ...)",),
        _wgpu("device.textures:_level_view", "stages.base:Stage.target_view"),
        "The same object; a default view covers the whole texture. A view is kept alive by what uses it, so "
        "there is no destroy order to get right.",
    ),
    Concept(
        "subresources",
        ("VkImageSubresourceRange", "VkImageSubresourceLayers"),
        _raw("device.images:subresource_range", "device.images:subresource_layers", "device.textures:level_range",
             "device.textures:level_layers"),
        ("create_view(base_mip_level, mip_level_count, base_array_layer, array_layer_count, aspect)",
         "copy info {'texture', 'mip_level', 'origin', 'aspect'}"),
        _wgpu("device.textures:_level_view", "device.textures:read_mip", "device.native:clear_texture"),
        "The same ideas with keyword names; aspect defaults to 'all'. wgpu tracks usage per subresource, which "
        "is what lets it read one mip level while rendering into the next.",
    ),
    Concept(
        "layouts and transitions",
        ("VkImageLayout", "VkImageMemoryBarrier oldLayout -> newLayout",
         "VkAttachmentDescription initialLayout / finalLayout"),
        _raw("device.images:transition", "device.images:LAYOUT_ACCESS", "device.textures:transition_level",
             "device.textures:MipGenerator.__init__"),
        ("(none: implicit from usage)",),
        _wgpu("device.textures:upload_level", "device.textures:generate_mipmaps"),
        "wgpu has no image layouts: it tracks how each subresource was last used (copy destination, attachment, "
        "sampled) and records the transition itself before the next different use.",
    ),
    Concept(
        "swapchain",
        ("vkCreateSwapchainKHR", "vkGetSwapchainImagesKHR", "vkAcquireNextImageKHR",
         "re-creation on VK_ERROR_OUT_OF_DATE_KHR (the binding raises VkErrorOutOfDateKhr, VkSuboptimalKhr)"),
        _raw("window.swapchain:create_swapchain", "window.swapchain:acquire_next_image", "window:RawWindow.frame",
             "window:RawWindow._recreate"),
        ("GPUCanvasContext.configure(device=, format=, usage=)", "GPUCanvasContext.get_current_texture()",
         "set_physical_size"),
        _wgpu("window:DemoWindow.frame", "window:surface_format", "window:SURFACE_USAGE"),
        "Image count, image views and the acquire semaphore are hidden; get_current_texture() is acquire. A "
        "resize re-configures the context instead of re-creating a swapchain by hand; a minimised window "
        "(0x0) renders nothing, and an occluded one skips the frame (get_current_texture() raises "
        "wgpu.DrawCancelled where Vulkan's acquire returns VK_ERROR_OUT_OF_DATE_KHR or VK_SUBOPTIMAL_KHR). The "
        "raw window does all of it: minImageCount + 1 images, vkAcquireNextImageKHR "
        "with a semaphore, re-creation from the old swapchain on resize, SUBOPTIMAL or OUT_OF_DATE and after "
        "minimise, and a swapchain made with TRANSFER_DST (the stage's image is blitted in) and TRANSFER_SRC "
        "(--screenshot reads the presented image back).",
    ),
    Concept(
        "attachment descriptions and references",
        ("VkAttachmentDescription (format, samples, loadOp, storeOp, layouts)", "VkAttachmentReference"),
        _raw("device.renderpass:attachment", "device.renderpass:ref"),
        ("color_attachments=[{view, resolve_target, load_op, store_op, clear_value}]", "depth_stencil_attachment"),
        _wgpu("stages.base:Stage.color_attachment", "stages.cube3d:Cube3D.record"),
        "Attachments are given when the pass begins, not described in advance: the format comes from the view, "
        "there are no layouts, and store_op 'discard' is STORE_OP_DONT_CARE.",
    ),
    Concept(
        "subpasses and dependencies",
        ("VkSubpassDescription", "VkSubpassDependency (VK_SUBPASS_EXTERNAL, BY_REGION)", "vkCmdNextSubpass"),
        _raw("device.renderpass:single_pass", "device.renderpass:msaa_post_pass", "device.renderpass:dependency",
             "device.renderpass:into_pass", "device.renderpass:out_to_transfer",
             "scene.renderpass:create_scene_render_pass",
             "scene.frame:SceneFrame.record", "post.neighbourhood:NeighbourhoodPass"),
        ("(none: one subpass per render pass)",),
        _wgpu("stages.msaa_post:MsaaPost.record", "post.chain:PostRunner.run", "post.shaders:pass_source",
              "scene.frame:SceneRenderer.record"),
        "WebGPU cannot express subpasses (Metal and D3D12 have none; gfx-rs/wgpu#10148): each step is its own "
        "render pass, and the dependencies between passes are implied by their order in the encoder. The "
        "msaa-post stage shows it at its smallest: one render pass with two subpasses on the raw path, two "
        "render passes and a stored, re-read resolve on wgpu (docs/benchmarks.md measures the cost). What a "
        "subpass chain gives, the plan gets by fusing: consecutive per-pixel effects run as functions in one "
        "pass (post/shaders.py), in float32 registers like the raw subpass; final_subpass.toml, 320x240: "
        "bit-identical to the raw path. Unfused (render.post_fuse = false) the image goes through an "
        "rgba16float texture between effects (lavapipe rounds that store toward zero): 2697 pixels off by "
        "1/255, FLIP 0.00176, and bit-identical once the raw shader rounds the same way "
        "(tests/test_vulkan_ref_scene.py). A neighbourhood effect (fxaa, sharpen) is a render pass of its own "
        "on the raw path too, behind an explicit barrier, with the per-pixel effects after it in its subpass 1.",
    ),
    Concept(
        "barriers with stage and access masks",
        ("vkCmdPipelineBarrier", "VkBufferMemoryBarrier / VkImageMemoryBarrier",
         "VkPipelineStageFlags + VkAccessFlags (availability and visibility)"),
        _raw("device.images:transition", "device.memory:record_copy", "device.readback:record_copy_to_buffer",
             "device.textures:transition_level", "window:image_barrier"),
        ("(none: inserted by wgpu)",),
        _wgpu("device.textures:generate_mipmaps", "post.chain:PostRunner.run"),
        "No barrier is ever written: wgpu inserts them between passes and copies from its usage tracking, with "
        "stage and access masks of its own choice. The cost: no control over how narrow a barrier is, no "
        "barriers inside a render pass.",
    ),
    Concept(
        "fences",
        ("vkCreateFence", "vkQueueSubmit(..., fence)", "vkWaitForFences"),
        _raw("device.command_buffers:submit_and_wait", "window.swapchain:owned_fence", "window:FrameSlot.wait",
             "window:RawWindow.frame"),
        ("(no fence object)", "GPUBuffer.map_sync", "queue.on_submitted_work_done (broken in wgpu-py 0.32)"),
        _wgpu("device.context:GPUContext.wait_idle", "device.targets:read_texture"),
        "The host waits by mapping a buffer that the last submission wrote: submissions complete in order, so "
        "once the map resolves everything before it has finished. WebGPU has no fence object because it has no "
        "host-visible per-submission handle: the browser API it follows only promises a callback "
        "(onSubmittedWorkDone). The raw window uses one fence per frame in flight, made signalled, reset only "
        "after a successful acquire, waited on before the slot is recorded again.",
    ),
    Concept(
        "semaphores",
        ("vkCreateSemaphore", "VkSubmitInfo pWaitSemaphores / pSignalSemaphores / pWaitDstStageMask"),
        _raw("window.swapchain:owned_semaphore", "window:RawWindow.frame", "window.swapchain:present"),
        ("(none: queue submission order)",),
        _wgpu("window:DemoWindow.frame"),
        "No semaphores in wgpu: one queue, whose submissions run in order, and the acquire/present semaphores "
        "of the swapchain are inside get_current_texture() and present(). Their natural use is exactly there, "
        "and the raw window has both: image-available (one per frame slot, signalled by the acquire, waited on "
        "at the TRANSFER stage, so the stage renders before the image is free) and render-finished (one per "
        "swapchain image, signalled by the submit, waited on by the present). Headless rendering has none: one "
        "queue, nothing to hand over.",
    ),
    Concept(
        "frames in flight",
        ("MAX_FRAMES_IN_FLIGHT copies of VkCommandBuffer, VkFence and VkSemaphore", "vkWaitForFences before a "
         "slot is recorded again", "vkResetFences", "imagesInFlight fences"),
        _raw("window:FrameSlot", "window:RawWindow.frame"),
        ("(none: inside the surface)",),
        _wgpu("window:DemoWindow.frame"),
        "wgpu keeps its own frame pacing inside the surface (get_current_texture() blocks when the CPU runs too "
        "far ahead) and tracks resource lifetimes itself, so the wgpu window records one frame after another "
        "with no per-frame copies. The raw window keeps 2 frame slots, each with its own command buffer, fence, "
        "semaphore, offscreen image and framebuffers (freed when its fence signals), and waits on the fence of "
        "the slot that last used a swapchain image before reusing that image.",
    ),
    Concept(
        "events",
        ("vkCreateEvent", "vkCmdSetEvent / vkCmdWaitEvents (split barriers)"),
        (),
        ("(none)",),
        (),
        "Cannot be expressed in wgpu: there are no split barriers; wgpu places whole barriers where a resource "
        "changes use.",
        raw_note="not in the raw path: no natural use; a split barrier pays off when independent work can run "
        "between a write and its read, and in these frames every pass reads what the pass before it wrote",
        demonstrated=False,
    ),
    Concept(
        "render pass",
        ("vkCreateRenderPass", "vkCmdBeginRenderPass / vkCmdEndRenderPass"),
        _raw("device.renderpass:create_render_pass", "device.renderpass:RenderPass", "device.renderpass:begin",
             "stages.cube3d:Cube3D.record"),
        ("GPUCommandEncoder.begin_render_pass(...) -> GPURenderPassEncoder", "GPURenderPassEncoder.end()"),
        _wgpu("stages.triangle:Triangle.record", "stages.clear_pass:ClearPass.record"),
        "No render pass object is created ahead of time: begin_render_pass takes the attachments directly. A "
        "pipeline is compatible with any pass whose target formats and sample count match its own.",
    ),
    Concept(
        "framebuffer",
        ("vkCreateFramebuffer",),
        _raw("device.renderpass:create_framebuffer"),
        ("(none: the views go to begin_render_pass)",),
        _wgpu("stages.base:Stage.color_attachment"),
        "No framebuffer object: the views of a pass are listed when it begins.",
    ),
    Concept(
        "begin info and clear values",
        ("VkRenderPassBeginInfo (renderArea, pClearValues)", "VkClearValue", "VK_ATTACHMENT_LOAD_OP_CLEAR"),
        _raw("device.renderpass:begin", "device.renderpass:clear_color"),
        ("attachment {'load_op': 'clear', 'clear_value': ...}", "depth_clear_value"),
        _wgpu("stages.clear_pass:ClearPass.record", "stages.base:Stage.color_attachment"),
        "The clear value sits in each attachment instead of an array indexed like the attachments. The render "
        "area is always the whole attachment.",
    ),
    Concept(
        "pipeline",
        ("vkCreateGraphicsPipelines", "VkGraphicsPipelineCreateInfo"),
        _raw("device.pipeline:create_pipeline", "device.pipeline:PipelineDesc"),
        ("device.create_render_pipeline(layout=, vertex=, primitive=, depth_stencil=, multisample=, fragment=)",),
        _wgpu("stages.base:Stage.basic_pipeline", "stages.cube3d:Cube3D._pipeline",
              "stages.textured:TexturedPipelines._pipeline"),
        "No render pass or subpass: the fragment targets' formats and the sample count say what it draws into. "
        "Viewport and scissor are never part of it.",
    ),
    Concept(
        "pipeline layout",
        ("vkCreatePipelineLayout (pSetLayouts, pPushConstantRanges)",),
        _raw("device.pipeline:create_pipeline_layout"),
        ("device.create_pipeline_layout(bind_group_layouts=, immediate_size=)", "layout='auto'"),
        _wgpu("stages.cube3d:Cube3D.setup", "stages.textured:TexturedPipelines.__init__"),
        "Same shape; push constant ranges become one immediate_size shared by all stages. 'auto' derives the "
        "layout from the shaders (post effects use it through get_bind_group_layout).",
    ),
    Concept(
        "pipeline cache",
        ("vkCreatePipelineCache", "vkGetPipelineCacheData", "VkPipelineCacheCreateInfo (pInitialData)"),
        _raw("device.pipeline_cache:create_pipeline_cache", "device.pipeline_cache:save_pipeline_cache",
             "device.pipeline_cache:pipeline_cache_path"),
        ("native feature 'pipeline-cache' (requested when offered)",),
        _wgpu("device.context:OPTIONAL_FEATURES"),
        "wgpu-native has the feature but wgpu-py 0.32 has no call to create a cache, so the wgpu path only "
        "requests it; naga's compiled modules are not kept across runs.",
    ),
    Concept(
        "shader modules and SPIR-V",
        ("glslc (GLSL -> SPIR-V)", "vkCreateShaderModule (codeSize, pCode)"),
        _raw("device.shaders:compile_glsl", "device.shaders:create_shader_module", "device.shaders:glsl_path",
             "scene.variants:glsl_defines"),
        ("device.create_shader_module(code=WGSL or SPIR-V)",),
        _wgpu("device.shaders:create_shader_module", "device.shaders:load_wgsl",
              "core.shaders.shader_variants:specialise"),
        "WGSL text compiled by naga at run time (errors with line and column). naga also takes SPIR-V, but not "
        "a combined sampler2D and not subpassInput. Shader variants: WGSL has no preprocessor, so the wgpu path "
        "specialises its template in Python; the raw path passes glslc -D flags to one GLSL source.",
    ),
    Concept(
        "vertex input bindings and attributes",
        ("VkVertexInputBindingDescription", "VkVertexInputAttributeDescription", "vkCmdBindVertexBuffers"),
        _raw("stages.triangle_buffers:vertex_input", "stages.cube3d:vertex_input", "stages.textured:vertex_input",
             "stages.cube3d:Cube3D.record"),
        ("vertex={'buffers': [{array_stride, step_mode, attributes: [{shader_location, format, offset}]}]}",
         "GPURenderPassEncoder.set_vertex_buffer"),
        _wgpu("stages.triangle_buffers:VERTEX_LAYOUT", "stages.cube3d:VERTEX_LAYOUT",
              "stages.triangle_buffers:TriangleBuffers.record"),
        "A binding is its position in the buffers list; formats are named float32x3 instead of "
        "R32G32B32_SFLOAT. step_mode 'instance' is inputRate INSTANCE.",
    ),
    Concept(
        "input assembly",
        ("VkPipelineInputAssemblyStateCreateInfo (topology, primitiveRestartEnable)",),
        _raw("device.pipeline:create_pipeline"),
        ("primitive={'topology': ..., 'strip_index_format': ...}",),
        _wgpu("stages.base:Stage.basic_pipeline"),
        "No adjacency or patch topologies; primitive restart is implied for strips by strip_index_format.",
    ),
    Concept(
        "viewport and scissor",
        ("vkCmdSetViewport", "vkCmdSetScissor", "VkPipelineViewportStateCreateInfo"),
        _raw("device.pipeline:set_viewport_and_scissor", "stages.textured:set_viewport"),
        ("GPURenderPassEncoder.set_viewport(x, y, w, h, min_depth, max_depth)", "set_scissor_rect"),
        _wgpu("stages.textured:Textured.record"),
        "Always dynamic, defaulting to the whole attachment; one viewport. wgpu's NDC y points up, Vulkan's down: "
        "wgpu's Vulkan backend flips with a negative viewport height, and the raw path does the same so both "
        "draw the same image from the same positions.",
    ),
    Concept(
        "rasterizer",
        ("VkPipelineRasterizationStateCreateInfo (polygonMode, cullMode, frontFace, lineWidth, depthBias)",),
        _raw("device.pipeline:create_pipeline"),
        ("primitive={'front_face': ..., 'cull_mode': ...}", "depth_stencil depth_bias*"),
        _wgpu("stages.cube3d:Cube3D._pipeline", "stages.base:Stage.basic_pipeline"),
        "No polygon modes other than fill (line/point need native features), line width always 1, no "
        "rasterizer discard; depth bias lives in the depth-stencil state.",
    ),
    Concept(
        "multisample",
        ("VkPipelineMultisampleStateCreateInfo (rasterizationSamples)", "VkImageCreateInfo.samples",
         "VkSubpassDescription.pResolveAttachments"),
        _raw("device.pipeline:create_pipeline", "device.renderpass:single_pass",
             "stages.base:RefStage.transient_msaa_image",
             "render:check_msaa"),
        ("multisample={'count', 'mask', 'alpha_to_coverage_enabled'}", "create_texture(sample_count=)",
         "attachment 'resolve_target'"),
        _wgpu("stages.base:Stage.multisample_state", "stages.base:Stage.color_attachment", "stages.base:Stage.resize"),
        "Sample counts 1 and 4 only (what WebGPU guarantees). The resolve target is a field of the colour "
        "attachment, not of a subpass; discarding the samples is store_op 'discard'.",
    ),
    Concept(
        "dynamic state",
        ("VkPipelineDynamicStateCreateInfo", "VK_DYNAMIC_STATE_VIEWPORT / SCISSOR / ..."),
        _raw("device.pipeline:create_pipeline"),
        ("(no list: set_viewport, set_scissor_rect, set_blend_constant, set_stencil_reference are always dynamic)",),
        _wgpu("stages.textured:Textured.record"),
        "Nothing to declare: those four are always pass commands, everything else is baked into the pipeline "
        "(no extended dynamic state).",
    ),
    Concept(
        "depth/stencil",
        ("VkPipelineDepthStencilStateCreateInfo", "depth attachment (D32_SFLOAT)", "VkClearDepthStencilValue"),
        _raw("device.pipeline:create_pipeline", "device.renderpass:single_pass", "stages.cube3d:Cube3D.setup"),
        ("depth_stencil={'format', 'depth_write_enabled', 'depth_compare', 'stencil_front', ...}",
         "depth_stencil_attachment={'view', 'depth_load_op', 'depth_clear_value', ...}"),
        _wgpu("stages.cube3d:Cube3D._pipeline", "stages.cube3d:Cube3D.on_resize", "stages.cube3d:Cube3D.record"),
        "The depth format is part of the pipeline; no depth bounds test. Otherwise one to one.",
    ),
    Concept(
        "blending",
        ("VkPipelineColorBlendAttachmentState", "VkPipelineColorBlendStateCreateInfo (logicOp)"),
        _raw("device.pipeline:create_pipeline", "device.pipeline:ALL_COLOR"),
        ("fragment targets [{'format', 'blend': {'color', 'alpha'}, 'write_mask'}]",),
        _wgpu("stages.base:Stage.basic_pipeline", "stages.cube3d:Cube3D._pipeline"),
        "Per-target blend state like Vulkan's per-attachment one; no logic ops. None of our stages blend yet: "
        "both paths write all channels with blending off.",
    ),
    Concept(
        "input attachments",
        ("VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT", "VkSubpassDescription.pInputAttachments", "GLSL subpassLoad"),
        _raw("device.renderpass:msaa_post_pass", "stages.msaa_post:MsaaPost._setup_post", "post.chain:PostSubpass",
             "post.neighbourhood:NeighbourhoodPass._create_render_pass"),
        ("(none: the previous pass's texture, sampled in a new pass)",),
        _wgpu("stages.msaa_post:MsaaPost._post", "post.passes:FragmentPass.encode", "post.chain:PostRunner.run"),
        "Cannot be expressed (no subpasses; gfx-rs/wgpu#10148). The image goes through memory between passes, "
        "which a tiling GPU would have kept on chip; in exchange an effect may read neighbouring pixels "
        "(post/chain.py explains). The converse limits the raw path: subpassLoad reads only the fragment's own "
        "pixel, so fxaa and sharpen cut its chain: each samples the previous result in a render pass of its "
        "own. An sRGB or float input attachment reads exactly like the wgpu path's texture load: msaa-post and "
        "every repository scene are bit-identical across the paths (the unfused wgpu chain against the raw "
        "path rounding to float16 between per-pixel effects; the fused chain differs by 1/255 only after a "
        "neighbourhood effect, whose result the raw path stores).",
    ),
    Concept(
        "push constants",
        ("VkPushConstantRange", "vkCmdPushConstants", "GLSL layout(push_constant)"),
        _raw("stages.msaa_post:MsaaPost._setup_post", "stages.msaa_post:MsaaPost.record",
             "stages.cube3d:Cube3D._setup_descriptors", "stages.cube3d:Cube3D.record", "device.ubo:pack_draw",
             "scene.scene_subpass:SceneSubpass.record", "device.uniforms:pack_material"),
        ("native feature 'immediates'", "create_pipeline_layout(immediate_size=)",
         "GPURenderPassEncoder.set_immediates(offset, data, data_offset, size)", "WGSL var<immediate>"),
        _wgpu("stages.cube3d:Cube3D.setup", "stages.cube3d:Cube3D.record", "device.context:_build_context"),
        "Not in WebGPU proper: a wgpu-native feature ('immediates', up to max-immediate-size bytes), one range "
        "for all stages. Without it the 3d stage reads the same struct from a dynamic-offset uniform buffer.",
    ),
    Concept(
        "UBO alignment",
        ("std140 layout", "VkPhysicalDeviceLimits.minUniformBufferOffsetAlignment"),
        _raw("device.ubo:dynamic_stride", "device.ubo:pack_camera", "device.ubo:pack_object",
             "device.context:copy_limits",
             "device.uniforms:pack_camera"),
        ("WGSL uniform address space layout", "limit 'min-uniform-buffer-offset-alignment'"),
        _wgpu("core.shaders.uniforms:Struct.stride", "core.shaders.uniforms:Struct.pack",
              "core.shaders.uniforms:Struct.pack_many",
              "core.shaders.uniforms:wgsl_structs"),
        "WGSL's uniform layout equals std140 for these types and naga rejects a struct that breaks it. The wgpu "
        "path declares each struct once and generates both the packer and the WGSL text; the raw path packs by "
        "hand, as an independent check.",
    ),
    Concept(
        "offscreen readback",
        ("vkCmdCopyImageToBuffer", "VkBufferImageCopy (bufferRowLength)", "HOST_CACHED memory"),
        _raw("device.readback:record_copy_to_buffer", "device.readback:buffer_to_pixels"),
        ("GPUCommandEncoder.copy_texture_to_buffer", "GPUBuffer.map_sync / read_mapped"),
        _wgpu("device.targets:Readback.record", "device.targets:Readback.read", "device.targets:padded_bytes_per_row"),
        "Rows in the buffer must start at multiples of 256 bytes in wgpu (Vulkan packs them tightly), so the "
        "wgpu path pads and unpads.",
    ),
    Concept(
        "samplers",
        ("vkCreateSampler", "VkSamplerCreateInfo (filters, mipmapMode, addressMode*, minLod/maxLod, anisotropy)",
         "samplerAnisotropy device feature", "VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER / SAMPLED_IMAGE + SAMPLER"),
        _raw("device.textures:sampler_info", "device.textures:create_sampler", "device.context:create_device",
             "stages.textured:Textured._setup_descriptors"),
        ("device.create_sampler(mag_filter=, min_filter=, mipmap_filter=, address_mode_*=, lod_*_clamp=, "
         "max_anisotropy=)", "bind group entries {'sampler'} and {'texture'}"),
        _wgpu("device.textures:create_sampler", "device.textures:SamplerSpec",
              "stages.textured:TexturedPipelines.__init__"),
        "wgpu requires all three filters linear when max_anisotropy > 1 and turns on the anisotropy device "
        "feature itself; Vulkan needs samplerAnisotropy enabled at device creation. WGSL has no combined image "
        "sampler: the wgpu path's 'combined' half puts texture and sampler in one bind group instead.",
    ),
    Concept(
        "mipmaps",
        ("VkImageCreateInfo.mipLevels", "vkCmdBlitImage per level (the course)", "a render pass per level (here)"),
        _raw("device.textures:MipGenerator.record", "device.textures:level_count", "device.textures:level_size"),
        ("create_texture(mip_level_count=)", "a render pass per level into create_view(base_mip_level=)"),
        _wgpu("device.textures:generate_mipmaps", "device.textures:mip_level_count"),
        "WebGPU has no blit, so the wgpu path draws each level in a render pass (an exact box filter in linear "
        "light) and wgpu orders the passes; the raw path does the same in GLSL rather than the course's "
        "vkCmdBlitImage, whose bilinear filter differs, so the two chains compare bit for bit.",
    ),
    Concept(
        "buffer objects",
        ("vkCreateBuffer", "VkBufferCreateInfo (size, usage, sharingMode)", "vkBindBufferMemory",
         "VkBuffer and its memory freed with their owner (an ExitStack)"),
        _raw("device.memory:create_buffer"),
        ("device.create_buffer(size=, usage=)", "device.create_buffer_with_data(data=, usage=)",
         "BufferUsage.VERTEX / INDEX / UNIFORM / COPY_DST"),
        _wgpu("stages.triangle_buffers:TriangleBuffers.setup", "stages.cube3d:Cube3D.setup"),
        "One call makes the buffer and its memory; there is no sharing mode (one queue) and no explicit destroy "
        "(Python's garbage collector drops it, or buffer.destroy()). The usage flags are the same idea with "
        "WebGPU's names; wgpu checks every use against them.",
    ),
    Concept(
        "memory requirements",
        ("vkGetBufferMemoryRequirements", "vkGetImageMemoryRequirements", "VkMemoryRequirements (size, alignment, "
         "memoryTypeBits)"),
        _raw("device.memory:create_buffer", "device.images:create_image"),
        ("device.create_buffer(size=, usage=) (wgpu asks for the requirements and allocates inside)",
         "device.create_texture(size=, usage=)"),
        _wgpu("stages.cube3d:Cube3D.setup", "device.targets:create_target"),
        "Never visible: wgpu queries the requirements, rounds the size up to the alignment and picks a memory type "
        "from memoryTypeBits inside create_buffer / create_texture. The raw path allocates exactly "
        "requirements.size (often more than the buffer's size) from a type the mask allows.",
    ),
    Concept(
        "clear without a render pass",
        ("vkCmdClearColorImage", "VkClearColorValue", "VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL"),
        _raw("stages.clear:ClearTransfer.record"),
        ("GPUCommandEncoder.clear_texture (wgpu-native's wgpuCommandEncoderClearTexture, feature 'clear-texture', "
         "reached through the cffi handle)",),
        _wgpu("device.native:clear_texture", "stages.clear:ClearTransfer.record"),
        "WebGPU's clear is outside any pass like vkCmdClearColorImage, but takes no colour: it always writes "
        "zeros (a colour needs a render pass with load_op 'clear', the stage clear-pass). wgpu-py 0.32 does not "
        "wrap it, so the wgpu path calls wgpu-native through cffi; wgpu places the layout transition itself.",
    ),
    Concept(
        "draw calls",
        ("vkCmdDraw", "vkCmdDrawIndexed", "vkCmdBindVertexBuffers", "vkCmdBindIndexBuffer"),
        _raw("stages.triangle:Triangle.record", "stages.triangle_buffers:TriangleBuffers.record",
             "stages.cube3d:Cube3D.record"),
        ("GPURenderPassEncoder.draw(vertex_count, instance_count, first_vertex, first_instance)",
         "draw_indexed(index_count, ...)", "set_vertex_buffer / set_index_buffer"),
        _wgpu("stages.triangle:Triangle.record", "stages.triangle_buffers:TriangleBuffers.record",
              "stages.cube3d:Cube3D.record"),
        "The same calls with the same arguments, recorded on a pass encoder instead of a command buffer; the index "
        "format is given when the index buffer is bound ('uint16'), as in vkCmdBindIndexBuffer. Each draw is "
        "validated by wgpu (buffer sizes against the counts), which costs CPU time per call (docs/benchmarks.md).",
    ),
    Concept(
        "instanced draws",
        ("vkCmdDrawIndexed (instanceCount, firstInstance)", "GLSL gl_InstanceIndex",
         "VK_DESCRIPTOR_TYPE_STORAGE_BUFFER (per-instance data)"),
        _raw("scene.scene_subpass:SceneSubpass.record", "scene.scene_subpass:SceneSubpass._setup_sets"),
        ("GPURenderPassEncoder.draw_indexed(index_count, instance_count, first_index, base_vertex, first_instance)",
         "WGSL @builtin(instance_index)", "bind group entry {'buffer'} of type 'read-only-storage'"),
        _wgpu("scene.scene_pass:ScenePassRenderer.record_draws",
              "scene.scene_pass:ScenePassRenderer._setup_uniforms"),
        "The same numbers on both paths: the plan batches draws of one mesh, pipeline and material into one "
        "instanced draw (core/plan/batches.py), and every instance's world matrix sits in ONE storage buffer "
        "indexed by the instance index, which includes first_instance in WGSL as gl_InstanceIndex does in "
        "Vulkan. 10k copies cost one draw call: the CPU's work no longer grows with the count.",
    ),
    Concept(
        "device idle",
        ("vkDeviceWaitIdle",),
        _raw("window:RawWindow._recreate", "window:RawWindow.close", "device.context:VulkanContext.close"),
        ("wgpu-native's device poll with wait (wgpu-py's private _poll_wait)", "a fence buffer: map_sync"),
        _wgpu("device.context:GPUContext.wait_idle"),
        "WebGPU has no wait-idle: a program waits for a mapped buffer or queue.on_submitted_work_done (which "
        "raises TypeError in wgpu-py 0.32.0). The wgpu path waits in one place, on the calling thread; the raw "
        "window waits for the device before it re-creates the swapchain or destroys anything.",
    ),
    Concept(
        "compute pipelines",
        ("vkCreateComputePipelines", "VkComputePipelineCreateInfo", "vkCmdBindPipeline(COMPUTE)", "vkCmdDispatch"),
        _raw("scene.ibl:_compute_pipeline", "scene.ibl:_record"),
        ("device.create_compute_pipeline(layout=, compute={module, entry_point, constants})",
         "encoder.begin_compute_pass", "compute_pass.dispatch_workgroups"),
        _wgpu("post.passes:ComputePass.__init__", "post.passes:ComputePass.dispatch", "scene.ibl:scene_maps_buffer"),
        "The same object: a pipeline with one shader stage, bound in a compute pass and dispatched in workgroups "
        "(8x8 here, one thread per texel or pixel). Both paths make the image-based lighting maps this way "
        "(ibl.wgsl; ibl.comp, its GLSL twin, one variant per pass where WGSL names three entry points); Vulkan "
        "records the dispatch in any command buffer outside a render pass, wgpu in a compute pass. Only the wgpu "
        "path's post chain can run as compute (the plan's post_path knob: docs/benchmarks.md measures both): the "
        "raw one runs in fragment subpasses, whose input attachments a compute pass cannot read.",
    ),
    Concept(
        "storage images",
        ("VK_DESCRIPTOR_TYPE_STORAGE_IMAGE", "VK_IMAGE_USAGE_STORAGE_BIT", "GLSL imageStore"),
        (),
        ("bind group layout entry {'storage_texture': {'access': 'write-only', 'format': ...}}",
         "TextureUsage.STORAGE_BINDING", "WGSL texture_storage_2d, textureStore"),
        _wgpu("post.passes:ComputePass._entries", "post.passes:ComputePass.dispatch", "post.chain:attachment_usage"),
        "An sRGB format cannot be a storage texture (rgba8unorm-srgb is not storable): the compute pass writes "
        "rgba8unorm or a float format and copies into an sRGB output, or encodes sRGB in the shader.",
        raw_note="not in the raw path: its one compute pass (the IBL maps) writes storage buffers; its images are "
        "colour, depth and input attachments and sampled images",
    ),
]


# -- output ---------------------------------------------------------------------------------------


def short(location: str) -> str:
    """A location without the package prefix, for display."""
    return location.removeprefix(W).removeprefix(C)


def title(row: Concept) -> str:
    """The row's name, marked where neither path has code for it."""
    return row.name if row.demonstrated else f"{row.name} (not demonstrated)"


def raw_cell(row: Concept) -> list[str]:
    return [short(loc) for loc in row.raw] or [f"({row.raw_note})"]


def wgpu_cell(row: Concept) -> list[str]:
    return [short(loc) for loc in row.wgpu_where] or ["(nothing)"]


def _md(items) -> str:
    text = items if isinstance(items, str) else "<br>".join(f"`{i}`" if ":" in i and " " not in i else i
                                                           for i in items)
    return text.replace("|", "\\|")


MARKDOWN_HEADER = """\
# Vulkan -> wgpu: the course's concepts, side by side

<!-- GENERATED FILE: do not edit. -->
Generated from `wgpurender/concepts.py` by `python -m wgpurender.concepts > docs/vulkan-mapping.md`
(or `wgpurender concepts --markdown > docs/vulkan-mapping.md`); edit the data there and regenerate.
tests/test_concepts.py fails when this file is stale and checks that every code location below exists.

Locations are `module:function` (or `module:Class.method`): the raw path's under `wgpurender.raw_path.`
(Python `vulkan` binding, GLSL), the wgpu path's under `wgpurender.wgpu_path.` (shown without that prefix);
`core.*` is the API-free core (`wgpurender.core.`) the wgpu path generates its WGSL structs from.
"""


def markdown(rows: list[Concept] = CONCEPTS) -> str:
    lines = [
        MARKDOWN_HEADER,
        "| Concept | Vulkan | Raw path | wgpu | wgpu path | What differs |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for row in rows:
        cells = [title(row), _md(row.vulkan), _md(raw_cell(row)), _md(row.wgpu), _md(wgpu_cell(row)), _md(row.differs)]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def plain_text(rows: list[Concept] = CONCEPTS, width: int = 100) -> str:
    out = []
    for row in rows:
        out.append(title(row))
        for label, items in (
            ("Vulkan", row.vulkan),
            ("raw path", raw_cell(row)),
            ("wgpu", row.wgpu),
            ("wgpu path", wgpu_cell(row)),
            ("differs", [row.differs]),
        ):
            text = "; ".join(items)
            out.append(textwrap.fill(text, width, initial_indent=f"  {label + ':':<11}", subsequent_indent=" " * 13))
        out.append("")
    return "\n".join(out)


# -- checking ---------------------------------------------------------------------------------------


def resolve(location: str):
    """The object a ``module:attr.path`` location names; ImportError / AttributeError when it is gone."""
    module_name, _, path = location.partition(":")
    if not path:
        raise ValueError(f"location {location!r} is not 'module:attribute'")
    obj = importlib.import_module(module_name)
    for part in path.split("."):
        obj = getattr(obj, part)
    return obj


def main() -> int:
    sys.stdout.write(markdown())
    return 0


if __name__ == "__main__":
    sys.exit(main())
