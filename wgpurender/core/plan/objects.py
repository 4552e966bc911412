"""Every object the wgpu renderer creates for a plan, counted per device call, each with why it is there.

The plan lists passes, attachments, pipelines, textures and samplers; this module adds what they take
on the wgpu path: bind group layouts and bind groups, shader modules, pipeline layouts, the mip
chain's passes, so the whole of what a renderer makes for a scene can be compared with the plan
(tests/test_plan_is_what_is_built.py wraps every ``device.create_*`` call). ``kind`` is the device
call without ``create_`` (``create_buffer_with_data`` counts as ``buffer``).

How the wgpu path builds (wgpurender/wgpu_path/): the scene pass has a camera group (0) and an object
group (1, one storage buffer of every instance's block; none when the plan's instance_data is "vertex": the
blocks are then a vertex buffer stepped per instance and the material group is 1) shared by every draw, a
material group (2) per
distinct material (Draw.material_key) whose variant samples textures or reads its factors from a buffer
(no immediates), a shader module per
variant and a pipeline layout per pipeline; a mip chain is one render pass per level, each reading
the level above through its own bind group; a post pass has its shader, layout, parameter buffer
and one bind group. The scene pass's draws and each fragment post pass's draws are a render bundle, recorded
once (issue 22.2). Nothing here is made for an empty scene pass but the clear.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

# No import of .model: RenderPlan.objects calls this module, so it reads the plan by attribute (as explain.py).


@dataclass(frozen=True)
class GpuObject:
    """Objects of one ``kind`` the wgpu renderer creates for a plan: ``kind`` names the device call
    (``texture`` for ``create_texture``, ``bind_group`` for ``create_bind_group``...), ``count`` how many."""

    kind: str
    name: str
    count: int
    reason: str


def gpu_objects(plan: Any) -> tuple[GpuObject, ...]:
    """The objects of ``plan`` (a :class:`~.model.RenderPlan`) in the order the renderer makes them."""
    out: list[GpuObject] = []
    out.extend(_attachments(plan))
    out.extend(_scene_pass(plan))
    out.extend(_textures(plan))
    out.extend(_post(plan))
    return tuple(out)


def _attachments(plan: Any) -> list[GpuObject]:
    return [GpuObject("texture", a.name, 1, a.reasons[0]) for a in plan.attachments if a.role != "output"]


def material_group_needed(variant: Any, immediates: bool | None) -> bool:
    """Group 2 exists for a variant that samples textures (it reads uv) or reads its factors from a buffer."""
    return immediates is not True or "uv" in variant.vertex_attributes or "ibl" in variant.flags


def _scene_pass(plan: Any) -> list[GpuObject]:
    draws = plan.scene_pass.draws
    if not draws:
        return []
    immediates = plan.immediates
    out = [GpuObject("buffer", name, 1, what) for name, what in plan.buffers if not name.startswith("post-")]
    storage = plan.instance_data == "storage"
    out.append(GpuObject("bind_group_layout", "Camera-layout", 1, "group 0: the camera, shared by every scene "
                         "pipeline"))
    if storage:
        out.append(GpuObject("bind_group_layout", "Object-layout", 1, "group 1: world matrices, one read-only "
                             "storage buffer"))
    out.append(GpuObject("bind_group", "camera", 1, "group 0, bound once per pipeline, written when the camera "
                         "changes"))
    if storage:
        out.append(GpuObject("bind_group", "objects", 1, f"group 1, one for all {len(draws)} draw(s) "
                             f"({sum(d.instance_count for d in draws)} instances, read at instance_index)"))
    material_group = 2 if storage else 1  # per-instance vertex attributes need no object group
    when = " (if the device lacks immediates)" if immediates is None else ""
    pushed = {True: " + immediates", None: " (+ immediates if the device has them)", False: ""}[immediates]
    for v in plan.variants:
        if material_group_needed(v, immediates):
            users = [d for d in draws if d.variant_key == v.key]
            what = [feature for feature, _ in users[0].textures]
            parts = ([f"Material buffer slice{when}"] if immediates is not True else []) + (
                ["sampler", *what] if what else []) + (["the image-based lighting maps"] if "ibl" in v.flags else [])
            out.append(GpuObject("bind_group_layout", f"material {v.key}", 1, f"group {material_group}: "
                                 + ", ".join(parts)))
            materials = len({d.material_key() for d in users})
            out.append(GpuObject("bind_group", f"material {v.key}", materials,
                                 "one per distinct material (equal materials share it): "
                                 + ", ".join(d.label for d in users)))
    plain = {p.variant.key for p in plan.pipelines if not p.culled}  # a variant all of whose draws are culled: none
    for v in plan.variants:
        if v.key in plain:
            out.append(GpuObject("shader_module", f"scene {v.key}", 1, "scene.wgsl specialised for this variant"))
    culled = plan.culled_draws
    for key in dict.fromkeys(p.variant.key for p in plan.pipelines if p.culled):
        out.append(GpuObject("shader_module", f"scene {key} culled", 1, "the variant reading its instances through "
                             "the visible list (GPU culling)"))
    for p in plan.pipelines:
        out.append(GpuObject("pipeline_layout", f"scene {p.key}", 1, f"groups 0-{material_group}{pushed} of its "
                             "variant"))
        out.append(GpuObject("render_pipeline", f"scene {p.key}", 1, "a scene pipeline of the plan"))
    for s in plan.samplers:
        out.append(GpuObject("sampler", f"sampler anisotropy {s.spec.max_anisotropy}", 1, "; ".join(s.used_by)))
    out.append(GpuObject("render_bundle_encoder", "scene-draws", 1, f"the {len(draws)} draw(s) recorded once "
                         "(pipeline, bind groups, buffers, draw); each frame replays them with one call"))
    passes = plan.ibl_passes
    if passes:
        why = "the image-based lighting maps, made once into scene-ibl (ibl.wgsl)"
        out += [GpuObject(kind, "ibl", 1, why) for kind in ("shader_module", "bind_group_layout", "pipeline_layout",
                                                             "command_encoder")]
        out += [GpuObject(kind, "ibl", len(passes), f"one per compute pass: {', '.join(passes)}")
                for kind in ("compute_pipeline", "bind_group")]
    if culled:
        why = "GPU frustum culling (scene_cull.wgsl): one invocation per instance of a culled draw"
        out += [GpuObject(kind, "scene-cull", 1, why) for kind in ("bind_group_layout", "pipeline_layout",
                                                                   "shader_module", "compute_pipeline")]
        out.append(GpuObject("bind_group", "cull", len(culled), "one per culled draw: its Cull block, the objects, "
                             "the visible list and the indirect arguments"))
    return out


def _textures(plan: Any) -> list[GpuObject]:
    out = [GpuObject("texture", t.path.name, 1, "; ".join(t.used_by)) for t in plan.textures]
    for fmt in plan.mipmap_formats:
        why = f"mip generation for {fmt} textures (one pipeline per format)"
        out += [GpuObject(kind, f"mipmap {fmt}", 1, why)
                for kind in ("shader_module", "bind_group_layout", "pipeline_layout", "render_pipeline")]
    for t in plan.textures:
        if t.mipmaps and t.mip_levels is not None and t.mip_levels > 1:
            w, h = t.size
            out.append(GpuObject("command_encoder", f"mipmaps {t.path.name}", 1,
                                 "the mip chain's passes, submitted once"))
            out.append(GpuObject("bind_group", f"mipmaps {t.path.name}", t.mip_levels - 1,
                                 f"{w}x{h}: {t.mip_levels} levels, each below the top reads the one above"))
    return out


def post_shader_key(p: Any) -> tuple:
    """What makes two post passes share a shader (and its layout): the same WGSL (post/shaders.py)."""
    return (p.effect, p.path, p.output_format if p.path == "compute" else None, bool(p.copy_to), bool(p.mask))


def _post(plan: Any) -> list[GpuObject]:
    out: list[GpuObject] = []
    shaders: set[tuple] = set()
    for p in plan.post_passes:
        key = post_shader_key(p)
        if key not in shaders:
            shaders.add(key)
            why = f"post pass {p.index + 1}'s generated WGSL ({p.path})"
            out += [GpuObject(kind, f"post {p.effect}", 1, why)
                    for kind in ("shader_module", "bind_group_layout", "pipeline_layout")]
        if any(s.spec.params for s in p.steps):
            out.append(GpuObject("buffer", f"post-{p.effect}-params", 1, "uniform: PassParams"))
        out.append(GpuObject("bind_group", f"post {p.effect}", 1, f"post pass {p.index + 1}: its input"
                             + (" and the storage texture it writes" if p.path == "compute" else "")))
    for p in plan.post_passes:
        if p.path == "fragment":
            draws = "fs_mark and fs_main" if p.mask else "the full-screen triangle"
            out.append(GpuObject("render_bundle_encoder", f"post-{p.effect}", 1,
                                 f"post pass {p.index + 1}'s bind group, pipeline and {draws}, once per input"))
    for pl in plan.post_pipelines:
        kind = "compute_pipeline" if pl.stage == "compute" else "render_pipeline"
        out.append(GpuObject(kind, f"post {pl.key}", 1, "a post pipeline of the plan"))
    if any(p.steps[0].spec.filtering for p in plan.post_passes):
        out.append(GpuObject("sampler", "post-linear-clamp", 1, "an effect samples between pixels"))
    return out
