"""The render plan: what a scene needs on the GPU, derived from the scene and nothing else.

:func:`build_plan` turns a :class:`~wgpurender.scene.Scene` into pure data (no GPU
objects): attachments with formats and sample counts, passes in order, shader
variants and pipelines, textures and samplers. The scene renderer builds exactly
these; everything a scene does not use is left out:

- a shader variant is the frozen set of features one material needs
  (``albedo_map``, ``normal_map``, ``roughness_map``, ``lighting``, ``flip_v``,
  ``srgb_output``, and light counts ``directional_lights:N`` / ``point_lights:N``);
  no ``normal_map`` feature and no tangent attribute unless a lit material has a
  normal map; no lighting code (and no normal attribute) for unlit materials;
- no multisampled attachment and no resolve at ``msaa = 1``;
- no post pass at all when the chain is empty: the scene draws into the output;
- no HDR (rgba16float) image unless ``hdr = true`` or the chain tone-maps.

Every item carries the reason it is there (which scene key asked for it), and
:meth:`RenderPlan.explain` prints them. ``python -m wgpurender.plan SCENE.toml``
does that from the command line; :func:`explain_scene` is what the CLI calls.

Variant flags are plain identifiers so a template can test them with
``#if normal_map`` (wgpurender/shader_variants.py); the light counts are separate
numbers (``ShaderVariant.counts``) for array sizes.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

from .anisotropy import resolve_anisotropy
from .errors import UserError
from .post import effects_for_target, intermediate_count
from .scene import Material, Scene, load_scene

DEPTH_FORMAT = "depth32float"
HDR_FORMAT = "rgba16float"
LDR_SCENE_FORMAT = "rgba8unorm-srgb"  # 8-bit scene image for a post chain: shaders still see linear values
COLOR_TEXTURE_FORMAT = "rgba8unorm-srgb"  # albedo: sRGB-encoded image, decoded by the sampler
DATA_TEXTURE_FORMAT = "rgba8unorm"  # normal and roughness maps: values used as stored
PLAN_OUTPUT_FORMATS = ("rgba8unorm-srgb", "rgba8unorm", "rgba16float", "bgra8unorm-srgb", "bgra8unorm")
SAMPLE_COUNTS = (1, 4)
ATTACHMENT_ORDER = ("msaa-color", "depth", "scene-color", "post-intermediate", "output")  # the order passes use them

# Feature -> vertex attribute it needs (position is always there).
ATTRIBUTES = (("lighting", "normal"), ("uv", "uv"), ("normal_map", "tangent"))
TEXTURE_FEATURES = ("albedo_map", "normal_map", "roughness_map")


@dataclass(frozen=True)
class Attachment:
    """A texture a pass renders into or reads. ``role``: msaa-color, depth, scene-color, post-intermediate, output."""

    name: str
    role: str
    format: str
    size: tuple[int, int]
    sample_count: int
    reasons: tuple[str, ...]


@dataclass(frozen=True)
class ShaderVariant:
    """One specialisation of the scene shader: boolean ``flags``, light ``counts``, and why each is on."""

    flags: frozenset[str]
    counts: tuple[tuple[str, int], ...] = ()
    reasons: tuple[tuple[str, str], ...] = ()  # (feature, why), in a stable order

    @property
    def features(self) -> frozenset[str]:
        """Flags plus ``name:N`` for each light count, e.g. {"lighting", "point_lights:2"}."""
        return self.flags | {f"{name}:{n}" for name, n in self.counts}

    @property
    def key(self) -> str:
        """Stable text key, e.g. ``albedo_map+lighting+normal_map+point_lights:2``; ``base`` when empty."""
        return "+".join(sorted(self.features)) or "base"

    @property
    def vertex_attributes(self) -> tuple[str, ...]:
        uses_uv = bool(self.flags & set(TEXTURE_FEATURES))
        have = self.flags | ({"uv"} if uses_uv else set())
        return ("position",) + tuple(attr for feature, attr in ATTRIBUTES if feature in have)

    def count(self, name: str) -> int:
        return dict(self.counts).get(name, 0)


@dataclass(frozen=True)
class ScenePipeline:
    """A render pipeline for the scene pass: a variant drawn into one colour format and sample count."""

    variant: ShaderVariant
    color_format: str
    sample_count: int
    depth_format: str | None
    cull_mode: str = "back"
    front_face: str = "ccw"

    @property
    def key(self) -> str:
        depth = self.depth_format or "no-depth"
        return f"{self.variant.key} | {self.color_format} x{self.sample_count} | {depth}"


@dataclass(frozen=True)
class TextureUse:
    """A texture file to upload, the format it is uploaded as, and who samples it."""

    path: Path
    format: str
    mipmaps: bool
    used_by: tuple[str, ...]


@dataclass(frozen=True)
class SamplerUse:
    spec: object  # wgpurender.textures.SamplerSpec (frozen, hashable)
    used_by: tuple[str, ...]


@dataclass(frozen=True)
class Draw:
    """One model drawn in the scene pass, with its material and pipeline."""

    model_index: int
    model_path: Path
    label: str
    material: str
    variant_key: str
    pipeline_key: str
    textures: tuple[tuple[str, Path], ...] = ()  # (feature, file) actually sampled
    sampler: object | None = None  # SamplerSpec when any texture is sampled
    transform: tuple[tuple[float, ...], ...] = ()
    material_label: str = ""


@dataclass(frozen=True)
class ScenePass:
    """The pass that draws the models: into ``color`` (resolved into ``resolve_target`` when multisampled)."""

    color: str
    resolve_target: str | None
    depth: str | None
    clear_color: tuple[float, float, float, float]
    draws: tuple[Draw, ...]
    kind: str = "scene"

    @property
    def writes(self) -> str:
        return self.resolve_target or self.color


@dataclass(frozen=True)
class PostPass:
    """One full-screen effect: reads ``input``, writes ``output``."""

    index: int
    effect: str
    params: tuple[tuple[str, float | str], ...]
    input: str
    output: str
    input_format: str
    output_format: str
    reason: str
    notes: tuple[str, ...] = ()
    kind: str = "post"


@dataclass(frozen=True)
class RenderPlan:
    scene_path: Path
    size: tuple[int, int]
    output_format: str
    msaa: int
    attachments: tuple[Attachment, ...]
    passes: tuple[ScenePass | PostPass, ...]
    variants: tuple[ShaderVariant, ...]
    pipelines: tuple[ScenePipeline, ...]
    post_pipelines: tuple[tuple[str, str], ...]  # (effect, target format), one pipeline each
    textures: tuple[TextureUse, ...]
    samplers: tuple[SamplerUse, ...]
    camera_note: str = ""
    notes: tuple[str, ...] = field(default=())

    # -- queries -------------------------------------------------------------
    def attachment(self, name: str) -> Attachment:
        for a in self.attachments:
            if a.name == name:
                return a
        raise KeyError(name)

    def has_attachment(self, name: str) -> bool:
        return any(a.name == name for a in self.attachments)

    @property
    def scene_pass(self) -> ScenePass:
        return next(p for p in self.passes if isinstance(p, ScenePass))

    @property
    def post_passes(self) -> tuple[PostPass, ...]:
        return tuple(p for p in self.passes if isinstance(p, PostPass))

    @property
    def features(self) -> frozenset[str]:
        """Every feature of every variant."""
        return frozenset().union(*(v.features for v in self.variants)) if self.variants else frozenset()

    @property
    def vertex_attributes(self) -> frozenset[str]:
        return frozenset(a for v in self.variants for a in v.vertex_attributes)

    def variant(self, key: str) -> ShaderVariant:
        return next(v for v in self.variants if v.key == key)

    # -- text ----------------------------------------------------------------
    def explain(self) -> str:
        """Passes, attachments, pipelines, textures and samplers, each with what asked for it."""
        w, h = self.size
        out = [f"scene: {self.scene_path}", f"output: {w}x{h} {self.output_format}, msaa {self.msaa}"]
        if self.camera_note:
            out.append(f"camera: {self.camera_note}")
        out.append("")
        out.append("passes:")
        for i, p in enumerate(self.passes, start=1):
            out.extend(_explain_pass(i, p))
        out.append("")
        out.append("attachments:")
        for a in self.attachments:
            samples = f"{a.sample_count} sample{'s' if a.sample_count > 1 else ''}"
            out.append(f"  {a.name}: {a.format}, {a.size[0]}x{a.size[1]}, {samples} ({a.role})")
            out.extend(f"      <- {r}" for r in a.reasons)
        out.append("")
        out.append("scene pipelines:" if self.pipelines else "scene pipelines: none (no models)")
        for pl in self.pipelines:
            v = pl.variant
            out.append(f"  {pl.key}")
            out.append(f"      vertex attributes: {', '.join(v.vertex_attributes)}")
            if not v.reasons:
                out.append("      features: none (flat colour, unlit)")
            for feature, why in v.reasons:
                out.append(f"      {feature}: {why}")
            users = [d.label for d in self.scene_pass.draws if d.pipeline_key == pl.key]
            out.append(f"      used by: {', '.join(users)}")
        out.append("post pipelines: " + (", ".join(f"{e} -> {f}" for e, f in self.post_pipelines) or "none"))
        out.append("")
        out.append("textures:" if self.textures else "textures: none")
        for t in self.textures:
            mips = "with mipmaps" if t.mipmaps else "no mipmaps"
            shown = os.path.relpath(t.path, self.scene_path.parent)
            out.append(f"  {shown} as {t.format}, {mips} <- {'; '.join(t.used_by)}")
        out.append("samplers:" if self.samplers else "samplers: none")
        for s in self.samplers:
            spec = s.spec
            out.append(
                f"  filter {spec.min_filter}/{spec.mag_filter}, mipmap {spec.mipmap_filter}, "
                f"address {spec.address_mode_u}, anisotropy {spec.max_anisotropy} <- {'; '.join(s.used_by)}"
            )
        if self.notes:
            out.append("")
            out.append("notes:")
            out.extend(f"  - {n}" for n in self.notes)
        return "\n".join(out) + "\n"


def _explain_pass(number: int, p: ScenePass | PostPass) -> list[str]:
    if isinstance(p, ScenePass):
        into = f"{p.color} resolved into {p.resolve_target}" if p.resolve_target else p.color
        depth = f", depth attachment {p.depth}" if p.depth else ""
        clear = ", ".join(f"{c:g}" for c in p.clear_color)
        lines = [f"  {number}. scene: draw {len(p.draws)} model(s) into {into}{depth}, clear ({clear})"]
        lines.extend(f"       {d.label}: {d.material_label}, variant {d.variant_key}" for d in p.draws)
        return lines
    params = ", ".join(f"{k}={v}" for k, v in p.params)
    lines = [f"  {number}. post {p.effect}({params}): {p.input} ({p.input_format}) -> {p.output} ({p.output_format})",
             f"       <- {p.reason}"]
    lines.extend(f"       note: {n}" for n in p.notes)
    return lines


# ---------------------------------------------------------------------------
# Building the plan
# ---------------------------------------------------------------------------


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


def build_plan(scene: Scene, *, size: tuple[int, int] | None = None, output_format: str | None = None,
               msaa: int | None = None, anisotropy: str = "scene", adapter_type: str | None = None) -> RenderPlan:
    """The plan for ``scene``; ``size``, ``output_format`` and ``msaa`` override [render] (CLI flags).

    ``anisotropy`` ("scene" or "auto") with ``adapter_type`` (wgpu's adapter_type, e.g. "CPU"): the
    per-adapter anisotropy rule of wgpurender/anisotropy.py (the perf engineer's knob)."""
    _check_overrides(size, output_format, msaa)
    r = scene.render
    size = tuple(size or r.size)
    out_fmt = output_format or r.output_format
    msaa = msaa or r.msaa
    src = lambda key, value: f"render.{key} = {value}" + (" (overridden)" if value != getattr(r, key) else "")  # noqa: E731
    notes: list[str] = []

    # -- the post chain (with the srgb pass a plain 8-bit output needs) ------
    user_effects = [step.create() for step in scene.post]
    effects = effects_for_target(user_effects, out_fmt)
    has_post = bool(effects)
    tonemaps = [s for s in scene.post if s.effect == "tonemap"]

    # -- where the scene pass writes ------------------------------------------
    attachments: list[Attachment] = []
    if has_post:
        if r.hdr:
            scene_fmt, why = HDR_FORMAT, "render.hdr = true: the scene is lit in linear HDR"
        elif tonemaps:
            scene_fmt, why = HDR_FORMAT, f"post[{tonemaps[0].index}] tonemap maps HDR to [0, 1], so it needs HDR input"
        else:
            scene_fmt, why = LDR_SCENE_FORMAT, "render.hdr = false and no tone mapping: 8 bits (sRGB-encoded) suffice"
        attachments.append(Attachment("scene_color", "scene-color", scene_fmt, size, 1, (
            why, f"post[0] {effects[0].name} reads the scene image as a texture (WebGPU has no input attachments)")))
        scene_target = "scene_color"
    else:
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
        attachments.append(Attachment("msaa_color", "msaa-color", scene_fmt, size, msaa, (
            src("msaa", msaa) + f": drawn multisampled, resolved into {scene_target} at the end of the pass, "
            "samples discarded (store_op discard)",)))
        color_target = "msaa_color"
    if scene.models:
        attachments.append(Attachment("depth", "depth", DEPTH_FORMAT, size, msaa, (
            f"{len(scene.models)} model(s) drawn with depth testing"
            + (f"; {msaa} samples to match msaa_color" if msaa > 1 else ""),)))

    # -- post passes -----------------------------------------------------------
    n_temp = intermediate_count(len(effects))
    temps = ["post_a", "post_b"][:n_temp]
    for i, name in enumerate(temps):
        users = [j for j in range(len(effects) - 1) if j % 2 == i]
        attachments.append(Attachment(name, "post-intermediate", scene_fmt, size, 1, (
            "written by " + ", ".join(f"post[{j}] {effects[j].name}" for j in users)
            + f" and read by the next effect (ping-pong, same format as {scene_target})",)))
    passes: list[ScenePass | PostPass] = []
    post_passes: list[PostPass] = []
    for i, effect in enumerate(effects):
        src_name = scene_target if i == 0 else temps[(i - 1) % 2]
        dst_name = "output" if i == len(effects) - 1 else temps[i % 2]
        src_fmt = scene_fmt
        dst_fmt = out_fmt if dst_name == "output" else scene_fmt
        implicit = i >= len(user_effects)
        reason = (f"render.output_format = {out_fmt} does not encode sRGB: an srgb pass is appended"
                  if implicit else f"[[post]] #{i} effect = \"{effect.name}\"")
        post_passes.append(PostPass(i, effect.name, tuple(effect.params.items()), src_name, dst_name, src_fmt,
                                    dst_fmt, reason, effect.notes(src_fmt, dst_fmt)))

    out_reasons = [src("output_format", out_fmt)]
    out_reasons.append(f"written by post[{len(effects) - 1}] {effects[-1].name}" if has_post else
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
        mat = model.material
        first_time = id(mat) not in seen_materials
        seen_materials.add(id(mat))
        variant = material_variant(mat, directional, point, srgb_output, notes if first_time else [])
        variants.setdefault(variant.key, variant)
        pipeline = ScenePipeline(variant, scene_fmt, msaa, DEPTH_FORMAT)
        pipelines.setdefault(pipeline.key, pipeline)
        sampled = tuple((f, getattr(mat, f)) for f in TEXTURE_FEATURES if f in variant.flags)
        spec = mat.sampler.spec() if sampled else None
        if spec is not None:
            spec, why = resolve_anisotropy(spec, anisotropy, adapter_type)
            if why and first_time:
                notes.append(f"{_material_label(mat)} sampler: {why}")
        label = _material_label(mat)
        for feature, path in sampled:
            fmt = COLOR_TEXTURE_FORMAT if feature == "albedo_map" else DATA_TEXTURE_FORMAT
            who = f"{label} {feature}"
            old = textures.get((path, fmt))
            if old is None:
                textures[(path, fmt)] = TextureUse(path, fmt, mat.sampler.mipmaps, (who,))
            elif who not in old.used_by:
                textures[(path, fmt)] = TextureUse(path, fmt, old.mipmaps or mat.sampler.mipmaps, old.used_by + (who,))
        if spec is not None:
            old = samplers.get(spec)
            if old is None:
                samplers[spec] = SamplerUse(spec, (f"{label} sampler",))
            elif f"{label} sampler" not in old.used_by:
                samplers[spec] = SamplerUse(spec, old.used_by + (f"{label} sampler",))
        draws.append(Draw(model.index, model.path, model.label, mat.name, variant.key, pipeline.key, sampled, spec,
                          model.transform.matrix, label))

    scene_pass = ScenePass(color_target, scene_target if msaa > 1 else None, "depth" if scene.models else None,
                           r.clear_color, tuple(draws))
    passes = [scene_pass, *post_passes]
    post_pipelines = tuple(dict.fromkeys((p.effect, p.output_format) for p in post_passes))
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
    )


def plan_scene_file(path: str | Path, **overrides) -> RenderPlan:
    return build_plan(load_scene(path), **overrides)


def explain_scene(path: str | Path, **overrides) -> str:
    """The plan of a scene file as text (what ``render SCENE.toml --explain`` prints)."""
    return plan_scene_file(path, **overrides).explain()


def main(argv: list[str] | None = None) -> int:
    """``python -m wgpurender.plan SCENE.toml``: print the plan; UserError -> one line, exit 2."""
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1 or args[0] in ("-h", "--help"):
        print("usage: python -m wgpurender.plan SCENE.toml", file=sys.stderr)
        return 2
    try:
        sys.stdout.write(explain_scene(args[0]))
    except UserError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
