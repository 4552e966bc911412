"""Building the plan: :func:`build_plan` turns a scene (and knobs) into a :class:`~.model.RenderPlan`.

Only :func:`wgpurender.core.plan.resolve.resolve_plan` calls it (tests/test_one_plan.py checks): every plan is
resolved for its adapter there, so no entry point, tool or test builds a plan another way.

It reads like the plan's sections, each its own function: the knobs (:func:`knob_settings`), the scene
pass's targets (:mod:`.targets`), its draws with their materials, variants and pipelines (:mod:`.draws`),
textures and samplers (:mod:`.textures`), the post chain (:mod:`.post`) and the output.
"""

from __future__ import annotations

from wgpurender.core.course.effects import steps_for_target
from wgpurender.core.errors import UserError
from wgpurender.core.plan import culling
from wgpurender.core.plan.batches import OBJECT_BYTES
from wgpurender.core.plan.draws import PipelineTarget, SceneDraws, material_variant, plan_draws
from wgpurender.core.plan.instance_data import fit_binding, resolve_instance_data
from wgpurender.core.plan.mesh_loading import obj_keys, resolve_mesh_workers
from wgpurender.core.plan.model import (
    ATTACHMENT_ORDER,
    DEPTH_FORMAT,
    PLAN_OUTPUT_FORMATS,
    SAMPLE_COUNTS,
    Knobs,
    RenderPlan,
    ScenePass,
)
from wgpurender.core.plan.post import plan_post_passes, post_pipelines_of, resolve_immediates, resolve_post_path
from wgpurender.core.plan.targets import SceneTargets, output_attachment, plan_scene_targets
from wgpurender.core.scene import Scene, playback

__all__ = ["build_plan", "knob_settings", "material_variant"]


def _check_overrides(size, output_format, msaa) -> None:
    if output_format is not None and output_format not in PLAN_OUTPUT_FORMATS:
        raise UserError(f"unsupported output format {output_format!r}: choose one of {', '.join(PLAN_OUTPUT_FORMATS)}")
    if msaa is not None and msaa not in SAMPLE_COUNTS:
        raise UserError(f"MSAA {msaa}x is not supported: choose 1 or 4")
    if size is not None and (len(size) != 2 or min(size) < 1):
        raise UserError(f"bad size {size!r}: give (width, height), both at least 1")


def knob_settings(scene: Scene, knobs: Knobs) -> tuple[tuple[str, str, str], ...]:
    """Every knob's resolved value and why, in the order ``--explain`` shows them."""
    r = scene.render
    post_path, path_why = resolve_post_path(r, knobs)
    fuse = r.post_fuse if knobs.post_fuse is None else knobs.post_fuse
    fuse_why = ("knob post_fuse" if knobs.post_fuse is not None else f"render.post_fuse = {str(r.post_fuse).lower()}")
    immediates, immediates_why = resolve_immediates(knobs)
    instance_data, instance_why = resolve_instance_data(knobs.instance_data, knobs.adapter)
    return (
        ("depth_format", knobs.depth_format, "knob depth_format" if knobs.depth_format != DEPTH_FORMAT else
         "default: 32-bit float depth"),
        ("reverse_z", "on" if knobs.reverse_z else "off",
         "knob reverse_z: depth 1 at near, 0 at far; compare greater, clear 0" if knobs.reverse_z else
         "default: depth 0 at near, 1 at far; compare less, clear 1"),
        ("post_fuse", "on" if fuse else "off", fuse_why + (
            ": consecutive per-pixel effects share one pass" if fuse else ": one pass per effect (teaching)")),
        ("post_path", post_path, path_why),
        ("immediates", immediates, immediates_why),
        ("instance_data", instance_data, instance_why),
        ("post_intermediate", knobs.post_intermediate, _intermediate_why(knobs.post_intermediate)),
        ("output_storage", "on" if knobs.output_storage else "off",
         "offscreen output: a compute pass may write it directly" if knobs.output_storage else
         "knob output_storage: the output is a swapchain image, not a storage texture"),
    )


def _intermediate_why(knob: str) -> str:
    if knob == "auto":
        return ("the scene image's format between post passes (rgba16float on the compute path when that is 8-bit "
                "sRGB): today's image")
    if knob == "none":
        return "knob post_intermediate: nothing stored before FXAA, the effects before it recomputed for each read"
    return "knob post_intermediate: the format stored between post passes"


def _mesh_workers(draws, knob: str, models) -> tuple[str, str, str]:
    """The mesh_workers setting: how many worker processes read the draws' distinct OBJ files, and why."""
    files = {path for path, _ in obj_keys(draws, models)}
    workers, why = resolve_mesh_workers(knob, len(files))
    return "mesh_workers", str(workers), why


def _camera_note(scene: Scene) -> str:
    """The camera line(s) of ``--explain``: a convention's flip, and which camera is the view when a model file
    has cameras (each of the files' cameras listed, core/scene/gltf_cameras.py)."""
    lines = []
    if scene.camera.convention == "glm-vulkan":
        lines.append("convention glm-vulkan: the projection has proj[1][1] *= -1 for Vulkan's y-down NDC; "
                     "wgpu's NDC is y-up, so it is multiplied by diag(1, -1, 1, 1) to undo the flip "
                     "(front faces stay counter-clockwise)")
    if scene.camera.origin or any(m.suffix in (".gltf", ".glb") for m in scene.models):
        from wgpurender.core.scene.gltf_cameras import camera_note

        listed = camera_note(scene.camera, scene.models)
        if listed and not scene.camera.origin:
            lines.append("the view is the scene's [camera] (eye, target)")
        lines += listed
    return "\n  ".join(lines)


def left_out(scene: Scene, msaa_text: str, asked_msaa: int, targets: SceneTargets, drawn: SceneDraws,
             post_passes: list, immediates: str = "auto") -> tuple[tuple[str, str], ...]:
    """What a renderer could have made and this plan does not, and why (``--explain``'s "left out")."""
    out: list[tuple[str, str]] = []
    if not scene.models:
        clear = ", ".join(f"{c:g}" for c in scene.render.clear_color)
        out.append(("scene draws", f"no [[models]]: the scene pass only clears {targets.target} to render.clear_color "
                    f"({clear}); a render pass that clears is how WebGPU clears a texture (wgpu-py 0.32 wraps no "
                    "clear_texture); no scene pipeline, shader, buffer or bind group"))
        if asked_msaa > 1:
            out.append(("msaa_color", f"{msaa_text}, but there are no models: nothing to antialias, the clear is "
                        "single-sampled"))
        out.append(("depth", "no models: nothing is depth-tested"))
    elif asked_msaa == 1:
        out.append(("msaa_color", f"{msaa_text}: drawn single-sampled, no resolve"))
    if not post_passes:
        out.append(("scene_color, post passes", "no [[post]] effects: the scene pass writes the output itself"))
    if scene.models and not scene.lights and not all(m.material.unlit for m in scene.models):
        out.append(("lighting", "the scene has no [[lights]]: a lit material keeps only its ambient term, drawn by "
                    "the unlit variant (no normals, light structs or lighting code)"))
    if scene.environment is not None and not any("ibl" in v.flags for v in drawn.variants.values()):
        out.append(("image-based lighting maps", f"[environment] {scene.environment.label} is given, but no lit glTF "
                    "metallic-roughness material draws in this scene: no maps, no buffer, no binding"))
    if scene.models and immediates == "on":
        out.append(("scene-materials buffer", "immediates on: each draw's material factors are pushed with the "
                    "draw, so no Material buffer (and no material bind group unless it samples textures)"))
    if scene.models and not drawn.textures:
        out.append(("textures, samplers, mip chains", "no material samples a texture (albedo_map, normal_map, "
                    "roughness_map)"))
    return tuple(out)


def build_plan(scene: Scene, *, size: tuple[int, int] | None = None, output_format: str | None = None,
               msaa: int | None = None, knobs: Knobs | None = None) -> RenderPlan:
    """The plan for ``scene``; ``size``, ``output_format`` and ``msaa`` override [render] (CLI flags);
    ``knobs`` (:class:`Knobs`) make the choices a scene file does not (depth, post path, adapter...).

    Sections, in order: knobs; targets (scene image, MSAA colour, depth); the scene pass's draws
    (variants, pipelines, materials, textures, samplers); the post chain; the output."""
    _check_overrides(size, output_format, msaa)
    knobs = knobs or Knobs()
    knobs.check()
    aniso_adapter = knobs.adapter.adapter_type if knobs.adapter is not None else None
    r = scene.render
    size = tuple(size or r.size)
    out_fmt = output_format or r.output_format
    asked_msaa = msaa or r.msaa
    msaa = asked_msaa if scene.models else 1  # no models: nothing to antialias, the pass only clears
    src = lambda key, value: f"render.{key} = {value}" + (" (overridden)" if value != getattr(r, key) else "")  # noqa: E731
    notes: list[str] = []
    settings = knob_settings(scene, knobs)
    setting = dict((k, v) for k, v, _ in settings)
    depth_compare = "greater" if knobs.reverse_z else "less"

    # the post chain's steps (with the srgb step a plain 8-bit output needs) decide where the scene pass writes
    steps = steps_for_target([s.step() for s in scene.post], out_fmt)
    targets = plan_scene_targets(scene, steps, out_fmt, size, msaa, src("msaa", msaa), knobs, depth_compare, notes)
    drawn = plan_draws(scene, PipelineTarget(targets.format, msaa, knobs.depth_format, depth_compare),
                       targets.srgb_output, knobs, aniso_adapter, notes)
    features = knobs.adapter.features if knobs.adapter is not None else None
    compute = knobs.adapter is None or knobs.adapter.compute
    ibl = any("ibl" in v.flags for v in drawn.variants.values())
    if knobs.adapter is not None and not (knobs.adapter.storage and knobs.adapter.compute) and ibl:
        lacks = ("storage buffers (a GL context below 4.0)" if not knobs.adapter.storage
                 else "compute shaders (a GL context below 4.3)")
        raise UserError(f"[environment] cannot be drawn on {knobs.adapter.name or knobs.adapter.backend}: its "
                        "image-based lighting maps are made by compute passes into a storage buffer the fragment "
                        f"shader reads, and this device offers no {lacks}; render with --backend vulkan")
    way = fit_binding(setting["instance_data"], dict((k, w) for k, _, w in settings)["instance_data"],
                      knobs.instance_data, sum(d.instance_count for d in drawn.draws), OBJECT_BYTES, knobs.adapter)
    settings = tuple((k, *way) if k == "instance_data" else (k, v, w) for k, v, w in settings)
    setting["instance_data"] = way[0]
    drawn.draws, cull, cull_why = culling.decide(drawn.draws, drawn.pipelines, knobs.culling, features,
                                                 setting["instance_data"], compute)
    settings = (*settings, ("culling", cull, cull_why), _mesh_workers(drawn.draws, knobs.mesh_workers, scene.models))
    scene_pass = ScenePass(targets.color, targets.target if msaa > 1 else None, targets.depth, r.clear_color,
                           tuple(drawn.draws), depth_clear=0.0 if knobs.reverse_z else 1.0)
    post_passes, post_attachments = plan_post_passes(steps, setting["post_fuse"] == "on", setting["post_path"],
                                                     targets.target, targets.format, out_fmt, size,
                                                     knobs.output_storage, intermediate=knobs.post_intermediate)
    last_post = f"written by post pass {len(post_passes)} ({post_passes[-1].effect})" if post_passes else None
    twin = post_passes[-1] if post_passes and post_passes[-1].twin_of else None
    output = output_attachment(twin.output_format if twin else out_fmt, size, src("output_format", out_fmt),
                               last_post, msaa > 1, twin.twin_of if twin else None)
    attachments = (*targets.attachments, *post_attachments, output)
    absent = left_out(scene, src("msaa", asked_msaa), asked_msaa, targets, drawn, post_passes, setting["immediates"])
    return RenderPlan(
        scene_path=scene.path,
        size=size,
        output_format=out_fmt,
        msaa=msaa,
        msaa_asked=asked_msaa,
        attachments=tuple(sorted(attachments, key=lambda a: ATTACHMENT_ORDER.index(a.role))),
        passes=(scene_pass, *post_passes),
        variants=tuple(drawn.variants.values()),
        pipelines=tuple(drawn.pipelines.values()),
        post_pipelines=post_pipelines_of(post_passes),
        textures=drawn.textures,
        samplers=drawn.samplers,
        camera_note=_camera_note(scene),
        notes=tuple(notes),
        playing=playback.tracks(scene),
        knobs=knobs,
        settings=settings,
        absent=absent,
        scene=scene,
    )

