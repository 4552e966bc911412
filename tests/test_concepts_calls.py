"""The mapping table's code locations make the API calls their rows name (read with ``ast``, no GPU).

tests/test_concepts.py checks that every location imports; that cannot catch a row pointing at a wrong
but existing function. Here the source of every location is parsed:

- every ``vk*`` function a row names is *called* in the body of one of the row's raw locations
  (an extension function looked up by name through vkGetInstanceProcAddr counts);
- every raw location uses at least one Vulkan name of its row (a function, struct, enum or field),
  and every wgpu location at least one wgpu name of its row (a method, or a descriptor key such as
  ``load_op``); locations that legitimately do not (a packer, a helper that prepares data for the call,
  a constant) are listed below, each with the reason, so the exception is stated, not silent.
"""

from __future__ import annotations

import ast
import inspect
import re
import textwrap

import pytest

from wgpurender.concepts import CONCEPTS, resolve

VK_FUNCTION = re.compile(r"\bvk[A-Z]\w+")
VK_NAME = re.compile(r"\b(?:vk[A-Z]\w+|Vk[A-Z]\w+|VK_[A-Z0-9_]+|[a-z]+[A-Z]\w*)")
WGPU_NAME = re.compile(r"\b[a-z_][a-z0-9_]{3,}\b")

# vk functions a row names that the raw path deliberately does not call (the row's text says so).
NOT_CALLED = {("mipmaps", "vkCmdBlitImage"): "the row says the raw path draws each level in a render pass instead"}

# Locations that do not themselves use their row's API names, and why.
HELPERS = {
    "raw_path.device.validation:validation_features":
        "builds the VkValidationFeaturesEXT chained into vkCreateInstance",
    "raw_path.device.context:copy_limits": "copies the VkPhysicalDeviceLimits that vkGetPhysicalDeviceProperties read",
    "raw_path.device.context:get_vulkan": "the cached context: calls create_device, which makes the call",
    "raw_path.device.memory:find_memory_type": "pure search of the memory types for a memoryTypeBits mask",
    "raw_path.device.textures:upload_texture": "calls the staging helpers (create_buffer, write_host_buffer)",
    "raw_path.device.memory:upload_buffer":
        "the staging upload: a staging buffer (create_buffer, write_host_buffer), then record_copy's copy and barrier",
    "raw_path.stages.textured:Textured._setup_descriptors": "calls the descriptors module's helpers",
    "raw_path.stages.cube3d:Cube3D._setup_descriptors": "calls the descriptors module's helpers",
    "raw_path.device.textures:TextureImage.level": "a per-level view through the images module's helper",
    "raw_path.device.textures:MipGenerator.__init__": "sets up the per-level passes whose transitions record() makes",
    "raw_path.device.renderpass:RenderPass": "the dataclass that holds the render pass handle and its attachments",
    "raw_path.device.pipeline:PipelineDesc":
        "the dataclass of fixed-function state create_pipeline turns into the call",
    "raw_path.device.pipeline_cache:pipeline_cache_path": "where the pipeline cache's data is kept on disk",
    "raw_path.device.shaders:compile_glsl": "makes the SPIR-V that vkCreateShaderModule takes",
    "raw_path.device.shaders:glsl_path": "finds the GLSL source",
    "raw_path.scene.variants:glsl_defines": "the shader variant's #defines",
    "raw_path.stages.base:RefStage.transient_msaa_image": "asks the images helper for a multisampled image",
    "raw_path.render:check_msaa": "checks the requested sample count against the device's",
    "raw_path.stages.cube3d:Cube3D.setup": "creates the depth image and pipeline through helpers",
    "raw_path.window:create_window_context": "glfwCreateWindowSurface (the glfw binding's create_window_surface) "
                                               "makes the surface from the instance",
    "raw_path.window:RawWindow._recreate": "re-creates the swapchain through create_swapchain, passing the old one",
    "raw_path.device.ubo:pack_draw": "packs the push-constant bytes",
    "raw_path.device.uniforms:pack_material": "packs the push-constant bytes",
    "raw_path.device.ubo:dynamic_stride": "std140/dynamic-offset arithmetic",
    "raw_path.device.ubo:pack_camera": "std140 packer",
    "raw_path.device.ubo:pack_object": "std140 packer",
    "raw_path.device.uniforms:pack_camera": "std140 packer",
    "raw_path.device.readback:buffer_to_pixels": "reads the buffer that vkCmdCopyImageToBuffer filled",
    "raw_path.device.textures:MipGenerator.record":
        "draws each level in a render pass (the row says: not vkCmdBlitImage)",
    "raw_path.device.textures:level_count": "mip chain arithmetic",
    "raw_path.device.textures:level_size": "mip chain arithmetic",
    "window:surface_format": "picks the format passed to configure",
    "stages.clear_pass:ClearPass.record": "takes its clear attachment from Stage.color_attachment",
    "stages.cube3d:Cube3D.record": "staging row: calls update_uniforms, which writes the buffers",
    "render:render_stage": "command-buffer row: run_frames records and submits",
    "stages.base:Stage.resize": "multisample row: multisampled_texture creates the texture",
    "device.shaders:load_wgsl": "reads the WGSL that create_shader_module takes",
    "core.shaders.shader_variants:specialise": "specialises the WGSL that create_shader_module takes",
    "core.shaders.uniforms:Struct.pack": "the WGSL uniform-layout packer",
    "core.shaders.uniforms:wgsl_structs": "the WGSL struct declarations",
    "device.targets:padded_bytes_per_row": "row-padding arithmetic for copy_texture_to_buffer",
    "device.textures:mip_level_count": "mip chain arithmetic",
    "post.chain:attachment_usage": "adds TextureUsage.STORAGE_BINDING to the textures a compute pass writes",
}
# Data, not code: constants that hold values of the row's API.
DATA = {"device.context:GPUContext.queue", "device.context:OPTIONAL_FEATURES", "window:PRESENT_MODES",
        "window:SURFACE_USAGE",
        "raw_path.device.images:FORMATS", "raw_path.device.images:LAYOUT_ACCESS", "raw_path.device.pipeline:ALL_COLOR",
        "stages.triangle_buffers:VERTEX_LAYOUT", "stages.cube3d:VERTEX_LAYOUT"}


def _short(location: str) -> str:
    return location.removeprefix("wgpurender.wgpu_path.").removeprefix("wgpurender.")


def _tree(location: str) -> ast.AST | None:
    try:
        return ast.parse(textwrap.dedent(inspect.getsource(resolve(location))))
    except (TypeError, OSError):
        return None  # not a function or class: a constant or a field


def _calls(tree: ast.AST) -> set[str]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            func = node.func
            out.add(func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", ""))
            if out & {"vkGetInstanceProcAddr", "vkGetDeviceProcAddr"}:
                out |= {a.value for a in node.args if isinstance(a, ast.Constant) and isinstance(a.value, str)}
    return out


def _names(tree: ast.AST) -> set[str]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute):
            out.add(node.attr)
        elif isinstance(node, ast.Name):
            out.add(node.id)
        elif isinstance(node, ast.keyword) and node.arg:
            out.add(node.arg)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            out.add(node.value)  # wgpu-py descriptors are dicts: {"load_op": "clear"}
    return out


@pytest.mark.parametrize("row", [r for r in CONCEPTS if r.raw], ids=lambda r: r.name)
def test_every_named_vk_function_is_called_at_a_raw_location(row):
    called = set()
    for location in row.raw:
        tree = _tree(location)
        if tree is not None:
            called |= _calls(tree)
    named = set(VK_FUNCTION.findall(" ".join(row.vulkan)))
    missing = {f for f in named - called if (row.name, f) not in NOT_CALLED}
    assert not missing, (f"row {row.name!r} names {sorted(missing)}, but none of its raw locations "
                         f"{[_short(x) for x in row.raw]} calls it: point the row at the function that makes the call")


def _location_cases():
    for row in CONCEPTS:
        vulkan = set(VK_NAME.findall(" ".join(row.vulkan)))
        for location in row.raw:
            yield pytest.param(row.name, location, vulkan, id=f"{row.name}:{_short(location)}")
        if all(w.startswith("(none") for w in row.wgpu):
            continue  # the row says wgpu has no such call
        wgpu_names = set(WGPU_NAME.findall(" ".join(row.wgpu)))
        for location in row.wgpu_where:
            yield pytest.param(row.name, location, wgpu_names, id=f"{row.name}:{_short(location)}")


@pytest.mark.parametrize(("concept", "location", "api_names"), list(_location_cases()))
def test_each_location_uses_its_rows_api(concept, location, api_names):
    short = _short(location)
    tree = _tree(location)
    if tree is None:
        assert short in DATA, f"row {concept!r}: {short} is neither a function nor a class nor a listed constant"
        return
    if short in HELPERS:
        return
    used = _names(tree) & api_names
    assert used, (f"row {concept!r} points at {short}, whose body uses none of the API the row names "
                  f"({sorted(api_names)[:8]}): a wrong location, or a helper to list in HELPERS with its reason")


def test_the_exception_lists_name_existing_locations():
    everywhere = {_short(loc) for row in CONCEPTS for loc in (*row.raw, *row.wgpu_where)}
    stale = (set(HELPERS) | DATA) - everywhere
    assert not stale, f"no row points at {sorted(stale)} any more: remove them from HELPERS / DATA"
