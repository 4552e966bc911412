"""Subpass 0: every model of the plan drawn with its variant's pipeline, depth-tested, into the MSAA image.

The course's descriptor sets and push constants, as the cube3d stage uses them:

- set 0: the camera UBO (proj, view, eye, ambient, lights), UNIFORM_BUFFER seen by vertex and
  fragment stages, in HOST_VISIBLE memory written through a mapping;
- set 1: the objects (world, normal matrix, mirror sign), STORAGE_BUFFER: every instance's block in
  one buffer (core/plan/batches.py), read by the vertex shader at gl_InstanceIndex; each draw is one
  vkCmdDrawIndexed with instanceCount = its instances and firstInstance = where they start;
- set 2 (variants that sample textures): one COMBINED_IMAGE_SAMPLER per map (albedo 2, normal 3,
  roughness 4), one set per distinct material (Draw.material_key), written with vkUpdateDescriptorSets;
- push constants: the material factors (base colour, roughness, normal strength, specular),
  vkCmdPushConstants per draw, fragment stage.

Pipelines are made per (variant key, front face) from shaders_glsl/scene.vert|frag compiled with the
variant's -D flags (variants.py), through the process-wide VkPipelineCache; a mirroring world matrix
(negative determinant) turns the winding around, as on the wgpu path.
"""

from __future__ import annotations

from contextlib import ExitStack

import numpy as np
import vulkan as vk

from wgpurender.core.course.formats import is_srgb_map
from wgpurender.core.course.shading import AMBIENT
from wgpurender.core.plan import Draw, RenderPlan, ShaderVariant
from wgpurender.core.plan.batches import instance_blocks
from wgpurender.core.scene import Scene
from wgpurender.raw_path.device import descriptors
from wgpurender.raw_path.device import uniforms as U
from wgpurender.raw_path.device.context import VulkanContext
from wgpurender.raw_path.device.memory import HOST_MEMORY, create_buffer, write_host_buffer
from wgpurender.raw_path.device.pipeline import PipelineDesc, create_pipeline, create_pipeline_layout
from wgpurender.raw_path.device.renderpass import RenderPass
from wgpurender.raw_path.scene.resources import SceneResources, vertex_input
from wgpurender.raw_path.scene.variants import glsl_defines, is_lit

VERTEX, FRAGMENT = vk.VK_SHADER_STAGE_VERTEX_BIT, vk.VK_SHADER_STAGE_FRAGMENT_BIT
GRAPHICS = vk.VK_PIPELINE_BIND_POINT_GRAPHICS
READ_ONLY = vk.VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL
IBL_BINDING = 11  # set 2: the image-based lighting maps (scene.wgsl's group 2 binding 11)
TOPOLOGIES = {"triangle-list": vk.VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, "line-list": vk.VK_PRIMITIVE_TOPOLOGY_LINE_LIST,
              "point-list": vk.VK_PRIMITIVE_TOPOLOGY_POINT_LIST}  # the plan's (WebGPU's) names
TEXTURE_BINDINGS = {"albedo_map": 2, "normal_map": 3, "roughness_map": 4, "emissive_map": 7, "occlusion_map": 9,
                    "clearcoat_map": 12, "clearcoat_roughness_map": 14, "clearcoat_normal_map": 16}


def camera_block(scene: Scene, aspect: float) -> bytes:
    """The lit camera block (the unlit shaders declare only its first three members).

    ``convention = "glm-vulkan"`` scenes upload the projection as the tutorial writes it (with GLM's
    Y flip for Vulkan's y-down NDC): the viewport is then not flipped (see frame.set_viewport).
    """
    cam = scene.camera
    directional = [(np.asarray(lt.direction) / np.linalg.norm(lt.direction), np.asarray(lt.color) * lt.intensity)
                   for lt in scene.lights if lt.type == "directional"]
    point = [(lt.position, np.asarray(lt.color) * lt.intensity, lt.shape()) for lt in scene.lights
             if lt.type == "point"]
    return U.pack_camera(cam.source_projection(aspect), cam.view(), cam.eye_vector(), AMBIENT, directional, point)


def material_block(scene: Scene, draw: Draw, variant: ShaderVariant) -> bytes:
    """Push constant bytes: the plan's factors for the draw (core/plan/draws.py decides them, e.g. with a
    roughness map the map's G channel times the factor is the roughness; a lit material without lights is drawn
    unlit with its base colour times the ambient), the same values the wgpu path pushes; alpha-masked variants
    append the cutoff."""
    f = dict(draw.factors)
    coat = tuple(f[k] for k in ("clearcoat", "clearcoat_roughness", "clearcoat_normal_scale")) if "clearcoat" in f \
        else None
    extras = {"alpha_cutoff": f.get("alpha_cutoff"), "occlusion_strength": f.get("occlusion_strength"),
              "clearcoat": coat, "emissive": f.get("emissive")}
    if not is_lit(variant):
        return U.pack_material(f["base_color"], lit=False, **extras)
    reflectance = f["metallic"] if "metallic" in f else f["specular"]  # PBR: metallic in specular's place
    return U.pack_material(f["base_color"], True, f["roughness"], f["normal_strength"], reflectance, **extras)


def material_block_size(variant: ShaderVariant) -> int:
    """The push constant range of a variant: its block packed with zeros (what material_block writes)."""
    flags = variant.flags
    return len(U.pack_material((0.0,) * 4, is_lit(variant), alpha_cutoff=0.0 if "alpha_mask" in flags else None,
                               occlusion_strength=0.0 if "occlusion_map" in flags else None,
                               clearcoat=(0.0,) * 3 if "clearcoat" in flags else None,
                               emissive=(0.0,) * 3 if "emissive" in flags else None))


class SceneSubpass:
    """Set layouts, descriptor sets, UBOs and pipelines of subpass 0, and the draws."""

    def __init__(self, ctx: VulkanContext, owned: ExitStack, scene: Scene, plan: RenderPlan,
                 resources: SceneResources, render_pass: RenderPass) -> None:
        self.ctx, self.owned, self.scene, self.plan = ctx, owned, scene, plan
        self.resources, self.render_pass = resources, render_pass
        self.draws = plan.scene_pass.draws
        self.pipelines: dict[tuple[str, int], object] = {}
        self.layouts: dict[str, object] = {}
        if self.draws:
            self._setup_uniforms()
            self._setup_sets()
            self.draw_state = [self._draw_state(d) for d in self.draws]

    # -- uniform buffers -------------------------------------------------------
    def _setup_uniforms(self) -> None:
        ctx, owned = self.ctx, self.owned
        uniform = vk.VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT
        self.camera_buffer = create_buffer(ctx, owned, U.CAMERA_SIZE, uniform, HOST_MEMORY)
        blocks = instance_blocks(self.draws)
        self.objects_size = blocks.nbytes
        self.object_buffer = create_buffer(ctx, owned, blocks.nbytes, vk.VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                           HOST_MEMORY)
        write_host_buffer(ctx, self.object_buffer, blocks)

    # -- descriptor sets ---------------------------------------------------------
    def _material_bindings(self, variant: ShaderVariant) -> list:
        out = [descriptors.binding(b, vk.VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, FRAGMENT)
               for feature, b in TEXTURE_BINDINGS.items() if feature in variant.flags]
        if "ibl" in variant.flags:  # the image-based lighting maps (core/course/ibl_maps.py), read-only in GLSL
            out.append(descriptors.binding(IBL_BINDING, vk.VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, FRAGMENT))
        return out

    def ibl_buffer(self):
        """The scene's [environment] maps, made by compute passes (raw_path/scene/ibl.py, the twin of the wgpu
        path's) straight into one storage buffer in the packed layout."""
        if getattr(self, "_ibl_buffer", None) is None:
            from wgpurender.core.course.ibl_maps import scene_environment
            from wgpurender.raw_path.scene.ibl import scene_maps_buffer

            env = self.scene.environment
            self._ibl_buffer = scene_maps_buffer(self.ctx, self.owned, scene_environment(env), env.samples)
        return self._ibl_buffer

    def _setup_sets(self) -> None:
        ctx, owned = self.ctx, self.owned
        self.camera_bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VERTEX | FRAGMENT)]
        self.object_bindings = [descriptors.binding(0, vk.VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VERTEX)]
        self.camera_layout = descriptors.create_set_layout(ctx, owned, self.camera_bindings)
        self.object_layout = descriptors.create_set_layout(ctx, owned, self.object_bindings)
        self.material_layouts = {}
        for v in self.plan.variants:
            bindings = self._material_bindings(v)
            self.material_layouts[v.key] = (bindings, descriptors.create_set_layout(ctx, owned, bindings)
                                            if bindings else None)
        # Equal materials share one set (Draw.material_key): one per distinct material, first-use order.
        textured = list({d.material_key(): d for d in reversed(self.draws)
                         if self.material_layouts[d.variant_key][1] is not None}.values())[::-1]
        pool = descriptors.create_pool(ctx, owned, [self.camera_bindings, self.object_bindings]
                                       + [self.material_layouts[d.variant_key][0] for d in textured])
        sets = descriptors.allocate_sets(ctx, pool, [self.camera_layout, self.object_layout]
                                         + [self.material_layouts[d.variant_key][1] for d in textured])
        self.camera_set, self.object_set = sets[:2]
        self.material_sets = {d.material_key(): s for d, s in zip(textured, sets[2:], strict=True)}
        writes = [
            descriptors.write_buffer(self.camera_set, 0, self.camera_buffer.handle, 0, U.CAMERA_SIZE),
            descriptors.write_buffer(self.object_set, 0, self.object_buffer.handle, 0, self.objects_size,
                                     vk.VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
        ]
        for d in textured:
            if "ibl" in self.plan.variant(d.variant_key).flags:
                buffer, target = self.ibl_buffer(), self.material_sets[d.material_key()]
                writes.append(descriptors.write_buffer(target, IBL_BINDING, buffer.handle, 0, buffer.size,
                                                       vk.VK_DESCRIPTOR_TYPE_STORAGE_BUFFER))
            for feature, path in d.textures:
                sampler = self.resources.sampler(d.sampler_of(feature))  # each texture its own (glTF samplers)
                texture = self.resources.texture(path, srgb=is_srgb_map(feature))
                writes.append(descriptors.write_image(self.material_sets[d.material_key()], TEXTURE_BINDINGS[feature],
                                                      texture.view, READ_ONLY,
                                                      vk.VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, sampler))
        descriptors.update(ctx, writes)

    # -- pipelines ------------------------------------------------------------------
    def pipeline_layout(self, variant: ShaderVariant):
        if variant.key not in self.layouts:
            set_layouts = [self.camera_layout, self.object_layout]
            if self.material_layouts[variant.key][1] is not None:
                set_layouts.append(self.material_layouts[variant.key][1])
            size = material_block_size(variant)
            push = vk.VkPushConstantRange(stageFlags=FRAGMENT, offset=0, size=size)
            self.layouts[variant.key] = create_pipeline_layout(self.ctx, self.owned, set_layouts, [push])
        return self.layouts[variant.key]

    def pipeline(self, variant: ShaderVariant, front_face: int, double_sided: bool = False, blend: bool = False,
                 topology: str = "triangle-list"):
        key = (variant.key, front_face, double_sided, blend, topology)
        if key not in self.pipelines:
            bindings, attributes = vertex_input(variant.vertex_attributes)
            cull = vk.VK_CULL_MODE_NONE if double_sided else vk.VK_CULL_MODE_BACK_BIT
            desc = PipelineDesc("scene.vert", "scene.frag", bindings, attributes, samples=self.plan.msaa,
                                cull_mode=cull, front_face=front_face, depth_test=True,
                                subpass=0, defines=glsl_defines(variant), blend=blend,
                                topology=TOPOLOGIES[topology])
            self.pipelines[key] = create_pipeline(self.ctx, self.owned, desc, self.pipeline_layout(variant),
                                                  self.render_pass)
        return self.pipelines[key]

    def _draw_state(self, draw: Draw) -> tuple:
        variant = self.plan.variant(draw.variant_key)
        mirror = np.linalg.det(np.array(draw.transform)[:3, :3]) < 0  # every instance of a draw has this sign
        front = vk.VK_FRONT_FACE_CLOCKWISE if mirror else vk.VK_FRONT_FACE_COUNTER_CLOCKWISE
        material = vk.ffi.from_buffer(material_block(self.scene, draw, variant))
        planned = self.plan.pipeline(draw.pipeline_key)
        pipeline = self.pipeline(variant, front, planned.cull_mode == "none", planned.blend, planned.topology)
        return (pipeline, self.pipeline_layout(variant), self.material_sets.get(draw.material_key()),
                material, self.resources.mesh_buffers(draw), self.resources.index_range(draw), draw)

    # -- recording ---------------------------------------------------------------------
    def record(self, cmd, size: tuple[int, int]) -> None:
        """Write the camera UBO (host write before the submit) and record the draws into subpass 0."""
        if not self.draws:
            return
        write_host_buffer(self.ctx, self.camera_buffer, camera_block(self.scene, size[0] / size[1]))
        for pipeline, layout, material_set, material, buffers, (first, count), draw in self.draw_state:
            vk.vkCmdBindPipeline(cmd, GRAPHICS, pipeline)
            vk.vkCmdBindDescriptorSets(cmd, GRAPHICS, layout, 0, 2, [self.camera_set, self.object_set], 0, None)
            if material_set is not None:
                vk.vkCmdBindDescriptorSets(cmd, GRAPHICS, layout, 2, 1, [material_set], 0, None)
            vk.vkCmdPushConstants(cmd, layout, FRAGMENT, 0, len(material), material)
            vk.vkCmdBindVertexBuffers(cmd, 0, 1, [buffers.vertex.handle], [0])
            vk.vkCmdBindIndexBuffer(cmd, buffers.index.handle, 0, buffers.index_type)
            # instanceCount copies; gl_InstanceIndex starts at firstInstance (this draw's blocks in set 1)
            vk.vkCmdDrawIndexed(cmd, count, draw.instance_count, first, 0, draw.first_instance)
