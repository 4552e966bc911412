"""The scene pass: every model of the plan drawn with its variant's pipeline, depth-tested.

Uniform data follows the cube3d stage (wgpurender/wgpu_path/stages/cube3d.py): group 0 the camera
(proj, view, eye, lights) rewritten every frame; group 1 every instance's world and normal
matrix in ONE storage buffer, read at instance_index: each draw is one instanced draw_indexed
whose first_instance points at its instances (core/plan/batches.py batches the plan's draws);
per-draw material factors as immediates (push constants), or, without the "immediates"
feature, from a uniform buffer bound in the material's group 2 (one slice per distinct
material, Draw.material_key: equal materials share the slice and the group).

Pipelines are cached by variant key (plus the winding, which a mirroring world matrix
turns around): models whose materials need the same features share one pipeline.
"""

from __future__ import annotations

import functools

import numpy as np
import wgpu

from wgpurender.core.course.formats import map_format
from wgpurender.core.course.shading import AMBIENT, REVERSE_Z
from wgpurender.core.plan import Draw, RenderPlan, ScenePipeline, ShaderVariant
from wgpurender.core.plan.batches import instance_blocks
from wgpurender.core.plan.model import material_numbers
from wgpurender.core.scene import Scene
from wgpurender.wgpu_path.device.bind_groups import uniform_group, uniform_layout
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.gpu_cache import GpuCache
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.scene import shader_interface as L
from wgpurender.wgpu_path.scene.cpu_culling import CpuCuller
from wgpurender.wgpu_path.scene.culling import GpuCuller
from wgpurender.wgpu_path.scene.resources import MeshBuffers, SceneResources


def camera_values(scene: Scene, aspect: float) -> dict:
    """The lit Camera struct's values for a frame (the unlit shader reads only the first fields)."""
    directional = [lt for lt in scene.lights if lt.type == "directional"]
    point = [lt for lt in scene.lights if lt.type == "point"]
    empty = {"direction": (0.0, 0.0, 0.0, 0.0), "radiance": (0.0, 0.0, 0.0, 0.0)}
    dir_items = [{"direction": (*(np.asarray(lt.direction) / np.linalg.norm(lt.direction)), 0.0),
                  "radiance": (*(np.asarray(lt.color) * lt.intensity), 0.0)} for lt in directional]
    point_items = [_point_light(lt) for lt in point]
    cam = scene.camera
    return {
        "proj": cam.projection(aspect),
        "view": cam.view(),
        "eye": cam.eye_vector(),
        "ambient": (*AMBIENT, 0.0),
        "light_counts": (len(directional), len(point), 0, 0),
        "directional": dir_items + [empty] * (L.MAX_LIGHTS - len(dir_items)),
        "point": point_items + [{"position": (0.0,) * 4, "radiance": (0.0,) * 4, "spot": (0.0,) * 4}]
        * (L.MAX_LIGHTS - len(point_items)),
    }


def _point_light(light) -> dict:
    """A point (or spot) light's PointLight values: range in position.w, the cone in radiance.w and spot."""
    axis, scale, offset, reach = light.shape()
    return {"position": (*light.position, reach), "radiance": (*(np.asarray(light.color) * light.intensity), offset),
            "spot": (*axis, scale)}


def material_values(scene: Scene, draw: Draw, variant: ShaderVariant) -> dict:
    """The draw's Material values: the plan's factors (course.shading.material_factors, decided there)."""
    return dict(draw.factors)


class ScenePassRenderer:
    """Pipelines, uniform buffers and bind groups of a plan's scene pass, and the pass itself."""

    def __init__(self, ctx: GPUContext, scene: Scene, plan: RenderPlan, resources: SceneResources,
                 use_immediates: bool | None = None) -> None:
        self.ctx, self.scene, self.plan, self.resources = ctx, scene, plan, resources
        self.reverse_z = plan.reverse_z  # depth 1 at near, 0 at far: compare "greater", clear 0 (plan knob)
        self.uses_immediates = ctx.use_immediates(use_immediates)
        self.draws = plan.scene_pass.draws
        self.depth_clear = plan.scene_pass.depth_clear
        self.culler = self.cpu_culler = None
        self.instance_data = plan.instance_data  # "storage" or "vertex" (core/plan/instance_data.py)
        # Made once per renderer (their layouts are this renderer's): named, counted caches (gpu_cache.py).
        self.pipelines: GpuCache[wgpu.GPURenderPipeline] = GpuCache("scene-pipelines")
        self._modules: GpuCache[wgpu.GPUShaderModule] = GpuCache("scene-modules")
        self._material_layouts: GpuCache[tuple] = GpuCache("scene-material-layouts")
        if self.draws:
            self.resources.meshes.start_reading()  # worker processes read the files while the blocks are made
            try:  # neither needs a mesh (a CPU culler's bounds wait for the workers)
                self._setup_uniforms()
                self._setup_materials()
            finally:  # a refused mesh file is still the one error said, as when the meshes came first
                placed = self.resources.upload_meshes(self.draws)  # every mesh in two buffers, before the draws
            self._setup_draws(placed)
        self.bundle = self._make_bundle()

    # -- uniforms ----------------------------------------------------------------
    def _setup_uniforms(self) -> None:
        dev = self.ctx.device
        usage = wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST
        self.alignment = self.ctx.limit("min-uniform-buffer-offset-alignment")
        self.camera_buffer = dev.create_buffer(label="scene-camera", size=L.CAMERA.size, usage=usage)
        # Every instance's Object block, written once (static): one storage buffer read at instance_index, or a
        # vertex buffer stepped per instance (the plan's instance_data); the CPU culler rewrites a culled draw's part.
        blocks = instance_blocks(self.draws)
        if self.instance_data == "vertex":
            blocks = L.vertex_blocks(blocks)  # the mirror sign beside the third normal column (one attribute)
        kind = wgpu.BufferUsage.STORAGE if self.instance_data == "storage" else wgpu.BufferUsage.VERTEX
        self.object_buffer = dev.create_buffer_with_data(label="scene-objects", data=blocks, usage=kind
                                                         | wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.COPY_SRC)
        stages = wgpu.ShaderStage.VERTEX | wgpu.ShaderStage.FRAGMENT
        self.camera_layout = uniform_layout(dev, L.CAMERA, stages, dynamic=False)
        self.camera_group = uniform_group(dev, self.camera_layout, self.camera_buffer, L.CAMERA)
        self.culler = (GpuCuller(self.ctx, self.plan, self.resources, self.object_buffer, len(blocks))
                       if self.plan.culled_draws else None)
        self.cpu_culler = (CpuCuller(self.ctx, self.plan.cpu_culled_draws, self.resources.meshes, blocks,
                                     self.object_buffer) if self.plan.cpu_culled_draws else None)
        self.object_layout = self.object_group = None
        if self.instance_data == "storage":
            self._setup_object_group(blocks.nbytes)
        # Equal materials share one slice and one group (Draw.material_key): first-use order.
        self._draw_slots, self.material_slots = material_numbers(self.draws)
        # One slice per material, as wide as the largest Material block of the plan's variants (a model file's
        # material appends factors: 48 bytes with a clear coat, 64 with emission) at the adapter's offset alignment
        structs = {L.material_struct(self.plan.variant(k)) for k in {d.variant_key for d in self.draws}} or {L.MATERIAL}
        self.material_stride = max(s.stride(self.alignment) for s in structs)
        self.material_buffer = None
        if not self.uses_immediates:
            self.material_buffer = dev.create_buffer(label="scene-materials", usage=usage,
                                                     size=self.material_stride * len(self.material_slots))

    def _setup_object_group(self, nbytes: int) -> None:
        """Group 1 of the storage way: the Object blocks (and the GPU-culled draws' visible lists)."""
        dev = self.ctx.device
        read = {"type": "read-only-storage"}
        vertex = wgpu.ShaderStage.VERTEX
        entries = [{"binding": 0, "visibility": vertex, "buffer": {**read, "min_binding_size": L.OBJECT.size}}]
        resources = [{"binding": 0, "resource": {"buffer": self.object_buffer, "offset": 0, "size": nbytes}}]
        if self.culler is not None:  # binding 1: the culled draws' visible lists (unread by the other pipelines)
            entries.append({"binding": 1, "visibility": vertex, "buffer": read})
            resources.append({"binding": 1, "resource": {"buffer": self.culler.visible}})
        self.object_layout = dev.create_bind_group_layout(label="Object-layout", entries=entries)
        self.object_group = dev.create_bind_group(label="objects", layout=self.object_layout, entries=resources)

    # -- per draw: pipeline, material group, immediates --------------------------
    def _setup_materials(self) -> None:
        """Each draw's pipeline, material group and packed Material (textures loaded, pipelines made): no mesh
        needed, so this runs while worker processes read the mesh files."""
        self._draw_materials = []
        groups: dict[int, wgpu.GPUBindGroup | None] = {}  # by material slot (core/plan/model.material_numbers)
        packed: dict[int, bytes] = {}  # equal materials hold equal variants and factors: packed once (10k draws)
        pipelines: dict[str, wgpu.GPURenderPipeline] = {}  # by the plan's key: looked up once, not once a draw
        for draw, slot in zip(self.draws, self._draw_slots, strict=True):
            variant = self.plan.variant(draw.variant_key)
            if slot not in packed:
                packed[slot] = L.material_struct(variant).pack(material_values(self.scene, draw, variant))
            data = packed[slot]
            if slot not in groups:
                if self.material_buffer is not None:
                    self.ctx.queue.write_buffer(self.material_buffer, slot * self.material_stride, data)
                groups[slot] = self._material_group(variant, draw, slot)
            pipeline = pipelines.get(draw.pipeline_key)
            if pipeline is None:
                pipeline = pipelines[draw.pipeline_key] = self.pipeline(self.plan.pipeline(draw.pipeline_key))
            self._draw_materials.append((pipeline, groups[slot], data))

    def _setup_draws(self, placed: list[MeshBuffers]) -> None:
        """Each draw's state: its material part and its mesh's buffers (``placed``, the upload's, in draw order)
        and index range (a draw of the whole mesh: all of the indices its buffers hold)."""
        index_range = self.resources.index_range
        self.draw_state = [(draw, pipeline, group, data, buffers,
                            (0, buffers.index_count) if draw.part is None else index_range(draw))
                           for draw, (pipeline, group, data), buffers
                           in zip(self.draws, self._draw_materials, placed, strict=True)]

    def material_layout(self, variant: ShaderVariant) -> wgpu.GPUBindGroupLayout | None:
        """Group 2 for a variant: its textures and sampler, plus the Material UBO without immediates."""
        return self._material_layouts.get(variant.key, lambda: (self._make_material_layout(variant),))[0]

    def _make_material_layout(self, variant: ShaderVariant) -> wgpu.GPUBindGroupLayout | None:
        frag = wgpu.ShaderStage.FRAGMENT
        entries = []
        if not self.uses_immediates:
            entries.append({"binding": L.MATERIAL_BINDING, "visibility": frag,
                            "buffer": {"type": "uniform", "min_binding_size": L.material_struct(variant).size}})
        for feature, binding in L.TEXTURE_BINDINGS.items():
            if feature in variant.flags:
                entries.append({"binding": binding, "visibility": frag,
                                "texture": {"sample_type": "float", "view_dimension": "2d"}})
                entries.append({"binding": L.SAMPLER_BINDINGS[feature], "visibility": frag,
                                "sampler": {"type": "filtering"}})
        if "ibl" in variant.flags:
            entries.append({"binding": L.IBL_BINDING, "visibility": frag, "buffer": {"type": "read-only-storage"}})
        if not entries:
            return None
        return self.ctx.device.create_bind_group_layout(label=f"material {variant.key}", entries=entries)

    def _material_group(self, variant: ShaderVariant, draw: Draw, k: int) -> wgpu.GPUBindGroup | None:
        bgl = self.material_layout(variant)
        if bgl is None:
            return None
        entries = []
        if not self.uses_immediates:
            size = L.material_struct(variant).size
            entries.append({"binding": L.MATERIAL_BINDING, "resource": {
                "buffer": self.material_buffer, "offset": k * self.material_stride, "size": size}})
        for feature, path in draw.textures:
            texture = self.resources.texture(path, map_format(feature))
            entries.append({"binding": L.TEXTURE_BINDINGS[feature], "resource": texture.view})
            entries.append({"binding": L.SAMPLER_BINDINGS[feature],
                            "resource": self.resources.sampler(draw.sampler_of(feature))})
        if "ibl" in variant.flags:
            entries.append({"binding": L.IBL_BINDING, "resource": {"buffer": self.ibl_buffer()}})
        return self.ctx.device.create_bind_group(layout=bgl, entries=entries, label=f"{draw.label} material")

    def ibl_buffer(self) -> wgpu.GPUBuffer:
        """The image-based lighting maps of the scene's [environment], made once by compute passes (ibl.py) in
        core/course/ibl_maps.py's packed layout."""
        if getattr(self, "_ibl_buffer", None) is None:
            from wgpurender.core.course.ibl_maps import scene_environment
            from wgpurender.wgpu_path.scene.ibl import scene_maps_buffer

            env = self.scene.environment
            self._ibl_buffer = scene_maps_buffer(self.ctx, scene_environment(env), env.samples)
        return self._ibl_buffer

    def shader_module(self, variant: ShaderVariant, culled: bool = False) -> wgpu.GPUShaderModule:
        return self._modules.get(variant.key + (" culled" if culled else ""), lambda: create_shader_module(
            self.ctx.device, L.SHADER, L.shader_source(variant, self.uses_immediates, culled, self.instance_data)))

    def pipeline(self, planned: ScenePipeline) -> wgpu.GPURenderPipeline:
        """A pipeline the plan lists (a variant, formats, winding, depth test), made once."""
        return self.pipelines.get(planned.key, lambda: self._make_pipeline(planned))

    def _make_pipeline(self, planned: ScenePipeline) -> wgpu.GPURenderPipeline:
        variant = planned.variant
        layouts = [self.camera_layout] + ([self.object_layout] if self.object_layout is not None else [])
        material_bgl = self.material_layout(variant)
        if material_bgl is not None:
            layouts.append(material_bgl)
        immediate_size = L.material_struct(variant).size if self.uses_immediates else 0
        dev = self.ctx.device
        pipeline_layout = dev.create_pipeline_layout(bind_group_layouts=layouts, immediate_size=immediate_size)
        module = self.shader_module(variant, planned.culled)
        return dev.create_render_pipeline(
            label=f"scene {variant.key}",
            layout=pipeline_layout,
            vertex={"module": module, "entry_point": "vs_main", "buffers": [L.vertex_layout(variant)] + (
                [L.instance_layout(variant)] if self.instance_data == "vertex" else [])},
            primitive={"topology": planned.topology, "front_face": planned.front_face, "cull_mode": planned.cull_mode},
            depth_stencil={"format": planned.depth_format, "depth_write_enabled": not planned.blend,
                           "depth_compare": planned.depth_compare},
            multisample={"count": planned.sample_count, "mask": 0xFFFFFFFF, "alpha_to_coverage_enabled": False},
            fragment={"module": module, "entry_point": "fs_main", "targets": [_color_target(planned)]},
        )

    # -- the pass ------------------------------------------------------------------
    def _write_camera(self, aspect: float) -> bool:
        """Pack and upload the camera UBO, only when its inputs changed since the last upload.

        The scene (camera, lights) is frozen, so the inputs are the objects themselves, the aspect
        and the depth convention; packing is Python work per field, so it is skipped, not redone.
        """
        key = (self.scene.camera, self.scene.lights, aspect, self.reverse_z)
        if key == getattr(self, "_camera_key", None):
            return False
        camera = camera_values(self.scene, aspect)
        if self.reverse_z:
            camera["proj"] = REVERSE_Z @ camera["proj"]
        self.ctx.queue.write_buffer(self.camera_buffer, 0, L.CAMERA.pack(camera))
        if self.culler is not None:
            self.culler.write_planes(camera["proj"] @ camera["view"])
        if self.cpu_culler is not None and self.cpu_culler.update(camera["proj"] @ camera["view"]):
            self.bundle = self._make_bundle()  # a CPU-culled draw's instance count changed
        self._camera_key = key
        return True

    def record(self, encoder: wgpu.GPUCommandEncoder, color_attachment: dict, depth_view, aspect: float,
               timestamp_writes: dict | None = None) -> None:
        """Write the camera UBO for this frame and record the scene pass."""
        self.bound([color_attachment], depth_view, aspect)(encoder, timestamp_writes)

    def bound(self, color_attachments: list[dict], depth_view, aspect: float):
        """``record`` with its attachment dicts made now: ``bound(...)(encoder, timestamp_writes=None)`` records
        the pass (a frame that keeps its attachments makes them once; issue 31.4)."""
        depth = None
        if depth_view is not None:
            depth = {"view": depth_view, "depth_clear_value": self.depth_clear,
                     "depth_load_op": "clear", "depth_store_op": "discard"}
        return functools.partial(self._record_pass, color_attachments, depth, aspect)

    def _record_pass(self, color_attachments: list[dict], depth: dict | None, aspect: float,
                     encoder: wgpu.GPUCommandEncoder, timestamp_writes: dict | None = None) -> None:
        # The objects never move: the visible lists change only with the camera, so the culling pass runs then
        # (the first frame, a resize, an orbit step), and a still frame costs no call for culling.
        if self.draws and self._write_camera(aspect) and self.culler is not None:
            self.culler.record(encoder)
        render_pass = encoder.begin_render_pass(label="scene", color_attachments=color_attachments,
                                                depth_stencil_attachment=depth, timestamp_writes=timestamp_writes)
        if self.bundle is not None:
            render_pass.execute_bundles([self.bundle])
        render_pass.end()

    # -- the draws, recorded once ----------------------------------------------------
    def _make_bundle(self) -> wgpu.GPURenderBundle | None:
        """Every draw of the pass in one render bundle, recorded once: the frame replays it with one call.

        The draws are static (pipelines, bind groups, buffers, dynamic offsets and immediates never change
        between frames; the camera changes through its buffer's contents), so recording them per frame was
        ~8 wgpu-py calls per draw for nothing (issue 22.2). A bundle depends only on the attachments'
        formats and sample count, not on the textures, so a resize or a new swapchain image keeps it.
        """
        if not self.draws:
            return None
        first = self.plan.pipeline(self.draws[0].pipeline_key)
        encoder = self.ctx.device.create_render_bundle_encoder(
            label="scene-draws", color_formats=[first.color_format], depth_stencil_format=first.depth_format,
            sample_count=first.sample_count)
        self.record_draws(encoder)
        return encoder.finish(label="scene-draws")

    def record_draws(self, encoder) -> None:
        """Record every draw into a render pass or render bundle encoder (the bundle is made with this): state
        that does not change from the previous draw is not set again; each draw is one instanced draw_indexed."""
        last: list = [None] * 4
        material_group = L.material_group(self.instance_data)
        if self.instance_data == "vertex" and self.draws:  # slot 1: the Object blocks, stepped per instance
            encoder.set_vertex_buffer(1, self.object_buffer)
        for draw, pipeline, group, data, buffers, (first, count) in getattr(self, "draw_state", []):
            if pipeline is not last[0]:
                encoder.set_pipeline(pipeline)
                encoder.set_bind_group(0, self.camera_group)
                if self.object_group is not None:
                    encoder.set_bind_group(1, self.object_group)
                last[1] = last[2] = None  # a new layout: the material group and immediates are set again
            if group is not None and group is not last[2]:
                encoder.set_bind_group(material_group, group)
            if self.uses_immediates and data is not last[1]:  # equal material keys share one bytes object
                encoder.set_immediates(0, data, 0, len(data))
            # every draw names its mesh by first index and base vertex in the shared buffers bound at 0, the
            # GPU-culled one through its indirect block (GpuCuller): lavapipe's indirect draws ignore an index
            # buffer's bind offset (benchmarks/indirect_index_offset_probe.py), so none is ever bound at one
            bound = (buffers.vertex, buffers.index, buffers.index_format)
            if bound != last[3]:
                encoder.set_vertex_buffer(0, buffers.vertex)
                encoder.set_index_buffer(buffers.index, buffers.index_format)
            last = [pipeline, data, group, bound]
            if self.plan.pipeline(draw.pipeline_key).culled:  # its visible instances, as the GPU counted them
                encoder.draw_indexed_indirect(self.culler.indirect, self.culler.offset(draw))
                continue
            # the draw's part of the mesh (a file material's triangles), once per instance
            instances = self.cpu_culler.count(draw) if draw.cpu_culled else draw.instance_count
            first += buffers.first_index  # where the mesh's indices start in the shared buffer
            encoder.draw_indexed(count, instances, first, buffers.base_vertex, draw.first_instance)


def _color_target(planned: ScenePipeline) -> dict:
    """The colour target; alpha blending (glTF alphaMode BLEND) is source-over: rgb * a + dst * (1 - a)."""
    target = {"format": planned.color_format}
    if planned.blend:
        target["blend"] = {
            "color": {"src_factor": "src-alpha", "dst_factor": "one-minus-src-alpha", "operation": "add"},
            "alpha": {"src_factor": "one", "dst_factor": "one-minus-src-alpha", "operation": "add"},
        }
    return target
