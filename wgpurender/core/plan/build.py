"""Building the plan: :func:`build_plan` turns a scene (and knobs) into a :class:`~.model.RenderPlan`."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

from wgpurender.core.anisotropy import resolve_anisotropy
from wgpurender.core.course.effects import steps_for_target
from wgpurender.core.course.shading import material_factors
from wgpurender.core.errors import UserError
from wgpurender.core.plan import file_materials
from wgpurender.core.plan.model import (
    ATTACHMENT_ORDER,
    COLOR_TEXTURE_FORMAT,
    DATA_TEXTURE_FORMAT,
    DEPTH_FORMAT,
    HDR_FORMAT,
    LDR_SCENE_FORMAT,
    PLAN_OUTPUT_FORMATS,
    SAMPLE_COUNTS,
    TEXTURE_FEATURES,
    AdapterFacts,
    Attachment,
    Draw,
    Knobs,
    RenderPlan,
    SamplerUse,
    ScenePass,
    ScenePipeline,
    ShaderVariant,
    TextureUse,
)
from wgpurender.core.plan.post import plan_post_passes, post_pipelines_of, resolve_immediates, resolve_post_path
from wgpurender.core.scene import Material, Scene, load_scene


def _determinant3(matrix) -> float:
    (a, b, c), (d, e, f), (g, h, i) = (tuple(row[:3]) for row in matrix[:3])
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def _material_label(m: Material) -> str:
    return f"material '{m.name}'" if m.origin.startswith("[materials.") else m.origin


def _lights_text(lights: list[int]) -> str:
    return ", ".join(f"lights[{i}]" for i in lights)


def material_variant(material: Material, directional: list[int], point: list[int], srgb_output: str | None,
                     notes: list[str]) -> ShaderVariant:
    """The features one material needs, each with its reason; ignored settings become notes."""
    label = _material_label(material)
    n_directional, n_point = len(directional), len(point)
    reasons: list[tuple[str, str]] = []
    lit = not material.unlit
    if material.albedo_map:
        reasons.append(("albedo_map", f"{label} has albedo_map = '{material.as_written('albedo_map')}'"))
    if lit:
        how = "unlit = false" if material.as_written("unlit") else "unlit is not set (materials are lit by default)"
        reasons.append(("lighting", f"{label} is lit: {how}"))
        for key in ("normal_map", "roughness_map"):
            if getattr(material, key):
                reasons.append((key, f"{label} has {key} = '{material.as_written(key)}'"))
        if n_directional + n_point == 0:
            notes.append(f"{label} is lit but the scene has no [[lights]]: it gets no direct light")
    else:
        ignored = [k for k in ("normal_map", "roughness_map") if getattr(material, k)]
        if ignored:
            notes.append(f"{label}: {' and '.join(ignored)} ignored because unlit = true (no lighting to use them)")
    samples = any(f in TEXTURE_FEATURES for f, _ in reasons)
    if material.uv_flip_v:
        if samples:
            reasons.append(("flip_v", f"{label} has uv_flip_v = true"))
        else:
            notes.append(f"{label}: uv_flip_v ignored because it samples no texture")
    reasons.extend(file_materials.extra_reasons(material, label, lit, samples, notes))
    if srgb_output:
        reasons.append(("srgb_output", srgb_output))
    counts = []
    for kind, indices in (("directional", directional), ("point", point)):
        if lit and indices:
            counts.append((f"{kind}_lights", len(indices)))
            why = f"{label} is lit and the scene has {len(indices)} {kind} light(s): {_lights_text(indices)}"
            reasons.append((f"{kind}_lights:{len(indices)}", why))
    flags = frozenset(f for f, _ in reasons if ":" not in f)
    return ShaderVariant(flags=flags, counts=tuple(counts), reasons=tuple(reasons))


def _check_overrides(size, output_format, msaa) -> None:
    if output_format is not None and output_format not in PLAN_OUTPUT_FORMATS:
        raise UserError(f"unsupported output format {output_format!r}: choose one of {', '.join(PLAN_OUTPUT_FORMATS)}")
    if msaa is not None and msaa not in SAMPLE_COUNTS:
        raise UserError(f"MSAA {msaa}x is not supported: choose 1 or 4")
    if size is not None and (len(size) != 2 or min(size) < 1):
        raise UserError(f"bad size {size!r}: give (width, height), both at least 1")


def _scene_format(scene: Scene, knobs: Knobs, has_post: bool) -> tuple[str, str]:
    r = scene.render
    tonemaps = [s for s in scene.post if s.effect == "tonemap"]
    if knobs.scene_format is not None:
        return knobs.scene_format, f"knob scene_format = {knobs.scene_format}"
    if r.hdr:
        return HDR_FORMAT, "render.hdr = true: the scene is lit in linear HDR"
    if tonemaps:
        return HDR_FORMAT, f"post[{tonemaps[0].index}] tonemap maps HDR to [0, 1], so it needs HDR input"
    return LDR_SCENE_FORMAT, "render.hdr = false and no tone mapping: 8 bits (sRGB-encoded) suffice"


def _plan_draw(model, mat: Material, seen_materials: set, directional, point, srgb_output, notes: list, knobs,
               aniso_adapter, msaa: int, scene_fmt: str, depth_compare: str, variants: dict, pipelines: dict,
               textures: dict, samplers: dict) -> Draw:
    """One draw: a model with one material (its scene material, or one of its file's), and what it needs."""
    first_time = id(mat) not in seen_materials
    seen_materials.add(id(mat))
    variant = material_variant(mat, directional, point, srgb_output, notes if first_time else [])
    variants.setdefault(variant.key, variant)
    # A mirroring world matrix (negative determinant) turns the winding around: its own pipeline.
    front_face = "cw" if _determinant3(model.transform.matrix) < 0 else "ccw"
    pipeline = ScenePipeline(variant, scene_fmt, msaa, knobs.depth_format, front_face=front_face,
                             depth_compare=depth_compare, **file_materials.pipeline_state(mat))
    pipelines.setdefault(pipeline.key, pipeline)
    sampled = tuple((f, getattr(mat, f)) for f in TEXTURE_FEATURES if f in variant.flags)
    spec = mat.sampler.spec() if sampled else None
    label = _material_label(mat)
    own = []
    for feature, feature_spec in file_materials.texture_samplers(mat, sampled, spec):
        feature_spec, why = resolve_anisotropy(feature_spec, knobs.anisotropy, aniso_adapter)
        if why and first_time:
            notes.append(f"{label} sampler: {why}")
        own.append((feature, feature_spec))
    for feature, path in sampled:
        fmt = COLOR_TEXTURE_FORMAT if feature == "albedo_map" else DATA_TEXTURE_FORMAT
        who = f"{label} {feature}"
        mips = file_materials.texture_mipmaps(mat, feature)
        old = textures.get((path, fmt))
        if old is None:
            textures[(path, fmt)] = TextureUse(path, fmt, mips, (who,))
        elif who not in old.used_by:
            textures[(path, fmt)] = TextureUse(path, fmt, old.mipmaps or mips, old.used_by + (who,))
    for feature, feature_spec in own:
        who = f"{label} sampler" if not mat.texture_samplers else f"{label} {feature} sampler"
        old = samplers.get(feature_spec)
        if old is None:
            samplers[feature_spec] = SamplerUse(feature_spec, (who,))
        elif who not in old.used_by:
            samplers[feature_spec] = SamplerUse(feature_spec, old.used_by + (who,))
    factors = material_factors(tuple(mat.albedo_color), mat.roughness, "lighting" in variant.flags,
                               "roughness_map" in variant.flags,
                               **file_materials.factor_options(mat, variant.flags))
    draw_label = model.label if mat.part is None else f"{model.label} {mat.name.removeprefix(model.label).strip()}"
    return Draw(model.index, model.path, draw_label, mat.name, variant.key, pipeline.key, sampled,
                own[0][1] if own else None, model.transform.matrix, label, tuple(factors.items()), part=mat.part,
                samplers=tuple(own))


def build_plan(scene: Scene, *, size: tuple[int, int] | None = None, output_format: str | None = None,
               msaa: int | None = None, knobs: Knobs | None = None, anisotropy: str | None = None,
               adapter_type: str | None = None) -> RenderPlan:
    """The plan for ``scene``; ``size``, ``output_format`` and ``msaa`` override [render] (CLI flags);
    ``knobs`` (:class:`Knobs`) make the choices a scene file does not (depth, post path, adapter...)."""
    _check_overrides(size, output_format, msaa)
    knobs = knobs or Knobs()
    if anisotropy is not None or adapter_type is not None:  # the anisotropy rule's arguments (perf's knob)
        knobs = dataclasses.replace(knobs, anisotropy=anisotropy or knobs.anisotropy,
                                    anisotropy_adapter=adapter_type or knobs.anisotropy_adapter)
    aniso_adapter = knobs.adapter.adapter_type if knobs.adapter is not None else knobs.anisotropy_adapter
    knobs.check()
    r = scene.render
    size = tuple(size or r.size)
    out_fmt = output_format or r.output_format
    msaa = msaa or r.msaa
    src = lambda key, value: f"render.{key} = {value}" + (" (overridden)" if value != getattr(r, key) else "")  # noqa: E731
    notes: list[str] = []

    # -- knobs -------------------------------------------------------------------
    post_path, path_why = resolve_post_path(r, knobs)
    fuse = r.post_fuse if knobs.post_fuse is None else knobs.post_fuse
    fuse_why = ("knob post_fuse" if knobs.post_fuse is not None else f"render.post_fuse = {str(r.post_fuse).lower()}")
    immediates, immediates_why = resolve_immediates(knobs)
    depth_compare = "greater" if knobs.reverse_z else "less"
    settings = [
        ("depth_format", knobs.depth_format, "knob depth_format" if knobs.depth_format != DEPTH_FORMAT else
         "default: 32-bit float depth"),
        ("reverse_z", "on" if knobs.reverse_z else "off",
         "knob reverse_z: depth 1 at near, 0 at far; compare greater, clear 0" if knobs.reverse_z else
         "default: depth 0 at near, 1 at far; compare less, clear 1"),
        ("post_fuse", "on" if fuse else "off", fuse_why + (
            ": consecutive per-pixel effects share one pass" if fuse else ": one pass per effect (teaching)")),
        ("post_path", post_path, path_why),
        ("immediates", immediates, immediates_why),
        ("output_storage", "on" if knobs.output_storage else "off",
         "offscreen output: a compute pass may write it directly" if knobs.output_storage else
         "knob output_storage: the output is a swapchain image, not a storage texture"),
    ]

    # -- the post chain (with the srgb step a plain 8-bit output needs) ----------
    steps = steps_for_target([s.step() for s in scene.post], out_fmt)
    has_post = bool(steps)

    # -- where the scene pass writes ------------------------------------------
    attachments: list[Attachment] = []
    if has_post:
        scene_fmt, why = _scene_format(scene, knobs, True)
        attachments.append(Attachment("scene_color", "scene-color", scene_fmt, size, 1, (
            why, f"post[0] {steps[0].effect} reads the scene image as a texture (WebGPU has no input attachments)")))
        scene_target = "scene_color"
    else:
        if knobs.scene_format is not None:
            raise UserError(f"{scene.path}: the scene_format knob needs a scene image that a post chain reads, "
                            "but this scene draws straight into its output: add [[post]] effects or drop the knob")
        scene_fmt, scene_target = out_fmt, "output"
        if r.hdr and not out_fmt.endswith("float"):
            notes.append(f"render.hdr = true but no post effect reads an HDR image: the scene draws straight into the "
                         f"{out_fmt} output, clipping at 1 (add [[post]] effect = \"tonemap\" to use the HDR range)")

    srgb_output = None
    if not has_post and out_fmt in ("rgba8unorm", "bgra8unorm"):
        srgb_output = (f"the scene draws straight into the {out_fmt} output, which does not encode: "
                       "the fragment shader applies the sRGB curve")

    color_target = scene_target
    if msaa > 1:
        if scene_fmt == "rgba32float":
            raise UserError("rgba32float cannot be multisampled in WebGPU: use msaa 1 with it")
        attachments.append(Attachment("msaa_color", "msaa-color", scene_fmt, size, msaa, (
            src("msaa", msaa) + f": drawn multisampled, resolved into {scene_target} at the end of the pass, "
            "samples discarded (store_op discard)",)))
        color_target = "msaa_color"
    if scene.models:
        attachments.append(Attachment("depth", "depth", knobs.depth_format, size, msaa, (
            f"{len(scene.models)} model(s) drawn with depth testing (compare {depth_compare})"
            + (f"; {msaa} samples to match msaa_color" if msaa > 1 else ""),)))

    # -- post passes -----------------------------------------------------------
    post_passes, post_attachments = plan_post_passes(steps, fuse, post_path, scene_target, scene_fmt, out_fmt, size,
                                                     knobs.output_storage)
    attachments.extend(post_attachments)

    out_reasons = [src("output_format", out_fmt)]
    out_reasons.append(f"written by post pass {len(post_passes)} ({post_passes[-1].effect})" if has_post else
                       ("resolve target of the scene pass" if msaa > 1 else "the scene pass draws into it directly"))
    attachments.append(Attachment("output", "output", out_fmt, size, 1, tuple(out_reasons)))

    # -- variants, pipelines, draws, textures, samplers ------------------------
    directional = [light.index for light in scene.lights if light.type == "directional"]
    point = [light.index for light in scene.lights if light.type == "point"]
    variants: dict[str, ShaderVariant] = {}
    pipelines: dict[str, ScenePipeline] = {}
    textures: dict[tuple[Path, str], TextureUse] = {}
    samplers: dict[object, SamplerUse] = {}
    draws = []
    seen_materials: set[int] = set()
    for model in scene.models:
        materials, found = file_materials.draw_materials(model)
        if found is not None:
            notes.extend(file_materials.model_notes(model, found))
        for mat in materials:
            draws.append(_plan_draw(model, mat, seen_materials, directional, point, srgb_output, notes, knobs,
                                    aniso_adapter, msaa, scene_fmt, depth_compare, variants, pipelines, textures,
                                    samplers))
    # alpha-blended draws last (over everything opaque), in scene order among themselves: not sorted by depth
    draws.sort(key=lambda d: pipelines[d.pipeline_key].blend)

    scene_pass = ScenePass(color_target, scene_target if msaa > 1 else None, "depth" if scene.models else None,
                           r.clear_color, tuple(draws), depth_clear=0.0 if knobs.reverse_z else 1.0)
    passes = [scene_pass, *post_passes]
    post_pipelines = post_pipelines_of(post_passes)
    camera_note = ""
    if scene.camera.convention == "glm-vulkan":
        camera_note = ("convention glm-vulkan: the projection has proj[1][1] *= -1 for Vulkan's y-down NDC; "
                       "wgpu's NDC is y-up, so it is multiplied by diag(1, -1, 1, 1) to undo the flip "
                       "(front faces stay counter-clockwise)")
    return RenderPlan(
        scene_path=scene.path,
        size=size,
        output_format=out_fmt,
        msaa=msaa,
        attachments=tuple(sorted(attachments, key=lambda a: ATTACHMENT_ORDER.index(a.role))),
        passes=tuple(passes),
        variants=tuple(variants.values()),
        pipelines=tuple(pipelines.values()),
        post_pipelines=post_pipelines,
        textures=tuple(textures.values()),
        samplers=tuple(samplers.values()),
        camera_note=camera_note,
        notes=tuple(notes),
        knobs=knobs,
        settings=tuple(settings),
        scene=scene,
        rebuild=build_plan,
    )


def plan_scene_file(path: str | Path, **overrides) -> RenderPlan:
    return build_plan(load_scene(path), **overrides)


def explain_scene(path: str | Path, adapter: AdapterFacts | None = None, **overrides) -> str:
    """The plan of a scene file as text (what ``render SCENE.toml --explain`` prints); with ``adapter``, the
    "auto" knobs are decided for it, as the renderer decides them, so the text lists what it would create."""
    plan = plan_scene_file(path, **overrides)
    return (plan.with_knobs(adapter=adapter) if adapter is not None else plan).explain()


def main(argv: list[str] | None = None) -> int:
    """``python -m wgpurender.core.plan SCENE.toml``: print the plan; UserError -> one line, exit 2."""
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1 or args[0] in ("-h", "--help"):
        print("usage: python -m wgpurender.core.plan SCENE.toml", file=sys.stderr)
        return 2
    try:
        sys.stdout.write(explain_scene(args[0]))
    except UserError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    return 0
