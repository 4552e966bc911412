"""The scene pass's contents: per model, its material's shader variant, its pipeline, its draw.

One draw per model and material: a scene material gives one draw; a glTF model without one draws once per
file material its triangles use (:mod:`.file_materials`, ``Draw.part``). A material becomes a
:func:`material_variant` (the features it needs, each with its reason), the variant and the target formats a
:class:`~.model.ScenePipeline`, and what it samples goes to the :class:`~.textures.TextureTable`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from wgpurender.core.course.shading import AMBIENT, material_factors
from wgpurender.core.plan import batches, file_materials, shading_models
from wgpurender.core.plan.model import (
    TEXTURE_FEATURES,
    Draw,
    Knobs,
    SamplerUse,
    ScenePipeline,
    ShaderVariant,
    TextureUse,
)
from wgpurender.core.plan.textures import TextureTable, material_sampler
from wgpurender.core.scene import IDENTITY, Material, Model, Scene
from wgpurender.core.scene.gltf_lights import light_note
from wgpurender.core.view.transforms import determinants3


def material_label(m: Material) -> str:
    return f"material '{m.name}'" if m.origin.startswith("[materials.") else m.origin


def _lights_text(lights: list) -> str:
    """Light labels (``lights[i]``, or a model file's light) as one list; indices are scene lights."""
    return ", ".join(f"lights[{i}]" if isinstance(i, int) else str(i) for i in lights)


def material_variant(material: Material, directional: list[int], point: list[int], srgb_output: str | None,
                     notes: list[str], environment=None) -> ShaderVariant:
    """The features one material needs, each with its reason; ignored settings become notes.

    A lit material in a scene without lights gets no lighting: what remains of the shading is the ambient
    term (ambient x albedo), which the unlit variant draws with the base colour scaled by the ambient
    (:func:`draw_factors`): no normals, no light structs, no lighting code. Unless an occlusion map
    scales that ambient term: then it stays lit."""
    label = material_label(material)
    reasons: list[tuple[str, str]] = []
    occluded = bool(getattr(material, "occlusion_map", None))  # it shapes the ambient term: lit shading keeps it
    environment_lit = environment is not None and material.shading_model == shading_models.PBR
    lit = not material.unlit and (bool(directional or point) or occluded or environment_lit)
    if lit and not (directional or point or environment_lit):
        notes.append(f"{label} is lit, the scene has no [[lights]], but its occlusion map scales the ambient term: "
                     "it keeps the lit variant (ambient x albedo x occlusion)")
    if material.albedo_map:
        reasons.append(("albedo_map", f"{label} has albedo_map = '{material.as_written('albedo_map')}'"))
    maps = [k for k in ("normal_map", "roughness_map") if getattr(material, k)]
    if lit:
        how = "unlit = false" if material.as_written("unlit") else "unlit is not set (materials are lit by default)"
        reasons.append(("lighting", f"{label} is lit: {how}"))
        reasons.extend((key, f"{label} has {key} = '{material.as_written(key)}'") for key in maps)
    elif not material.unlit:
        also = f"; its {' and '.join(maps)} only shape(s) direct light: not sampled" if maps else ""
        notes.append(f"{label} is lit but the scene has no [[lights]]: only the ambient term remains (ambient x "
                     f"albedo), so it is drawn with the unlit variant, its base colour scaled by the ambient "
                     f"{AMBIENT}{also}")
    elif maps:
        notes.append(f"{label}: {' and '.join(maps)} ignored because unlit = true (no lighting to use them)")
    samples = any(f in TEXTURE_FEATURES for f, _ in reasons)
    if material.uv_flip_v:
        if samples:
            reasons.append(("flip_v", f"{label} has uv_flip_v = true"))
        else:
            notes.append(f"{label}: uv_flip_v ignored because it samples no texture")
    reasons.extend(file_materials.extra_reasons(material, label, lit, samples, notes))
    reasons.extend(file_materials.uv_slot_reasons(material, label, reasons))
    reasons.extend(shading_models.model_reasons(material, label, lit, "roughness_map" in maps, notes))
    reasons.extend(shading_models.ibl_reasons(material, label, lit, environment))
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


def ambient_only(material: Material, variant: ShaderVariant) -> bool:
    """A lit material drawn without lighting (the scene has no lights): its colour is ambient x albedo."""
    return not material.unlit and "lighting" not in variant.flags


def draw_factors(material: Material, variant: ShaderVariant) -> dict:
    """The draw's Material values (course.shading.material_factors); ambient-only: base colour x ambient."""
    base = tuple(material.albedo_color)
    if ambient_only(material, variant):
        base = (*(c * a for c, a in zip(base[:3], AMBIENT, strict=True)), *base[3:])
    return material_factors(base, material.roughness, "lighting" in variant.flags, "roughness_map" in variant.flags,
                            **file_materials.factor_options(material, variant.flags))


@dataclass(frozen=True)
class PipelineTarget:
    """What every scene pipeline shares: the pass's colour format, sample count, depth format and test."""

    color_format: str
    sample_count: int
    depth_format: str
    depth_compare: str

    def pipeline(self, variant: ShaderVariant, material: Material, mirror: bool) -> ScenePipeline:
        # A mirroring world matrix (negative determinant) turns the winding around: its own pipeline.
        front_face = "cw" if mirror else "ccw"
        return ScenePipeline(variant, self.color_format, self.sample_count, self.depth_format,
                             front_face=front_face, depth_compare=self.depth_compare,
                             **file_materials.pipeline_state(material))


@dataclass
class SceneDraws:
    """The scene pass's draws and everything they need, each listed once in first-use order."""

    draws: list[Draw] = field(default_factory=list)
    variants: dict[str, ShaderVariant] = field(default_factory=dict)
    pipelines: dict[str, ScenePipeline] = field(default_factory=dict)
    table: TextureTable = field(default_factory=TextureTable)

    @property
    def textures(self) -> tuple[TextureUse, ...]:
        return tuple(self.table.textures.values())

    @property
    def samplers(self) -> tuple[SamplerUse, ...]:
        return tuple(self.table.samplers.values())


def plan_draws(scene: Scene, target: PipelineTarget, srgb_output: str | None, knobs: Knobs,
               anisotropy_adapter: str | None, notes: list[str]) -> SceneDraws:
    """One draw per model and material; a material's notes are added the first time it is drawn. Alpha-blended
    draws (glTF alphaMode BLEND) go last, in scene order among themselves: not sorted by depth. Then draws of
    the same mesh, pipeline and material values become one instanced draw (:mod:`.batches`)."""

    directional = [light.label for light in scene.lights if light.type == "directional"]
    point = [light.label for light in scene.lights if light.type == "point"]
    notes.extend(light_note(light) for light in scene.lights if light.origin)
    out = SceneDraws()
    seen_materials: set[int] = set()
    shaded: dict[tuple[int, bool], _Shading] = {}  # one material's part of every draw, made once (10k models)
    for model in scene.models:
        materials, found = file_materials.draw_materials(model)
        if found is not None:
            notes.extend(file_materials.model_notes(model, found))
        notes.extend(f"{model.label}: {line}" for line in model.motion)
        for mat in materials:
            first_time = id(mat) not in seen_materials
            seen_materials.add(id(mat))
            for mirror, worlds in _copies(model):
                if mirror is None:  # IDENTITY: every model placed inside its file (10k of a distinct scene)
                    mirror = model.transform is not IDENTITY and model.transform.mirrors
                key = (id(mat), mirror)
                if key not in shaded:
                    shaded[key] = _shading(mat, target, srgb_output, knobs, anisotropy_adapter,
                                           notes if first_time else None, directional, point, out, mirror,
                                           scene.environment)
                draw = _plan_draw(model, shaded[key])
                out.draws.append(draw if worlds is None else batches.instanced(
                    draw, worlds, model.placements.description))
                first_time = False
    out.draws.sort(key=lambda d: out.pipelines[d.pipeline_key].blend)
    out.draws = batches.batch_draws(out.draws, {k: p.blend for k, p in out.pipelines.items()})
    return out


def _copies(model: Model) -> list[tuple[bool | None, object]]:
    """A model's copies as (mirror, world matrices) groups: one group per winding (a mirroring copy needs the
    clockwise pipeline); (None, None) for a model without ``instances`` (its transform decides)."""
    if model.placements is None:
        return [(None, None)]
    worlds = model.worlds()
    mirrored = determinants3(worlds) < 0
    return [(m, worlds[mirrored == m]) for m in dict.fromkeys(mirrored.tolist())]


@dataclass(frozen=True)
class _Shading:
    """What a draw takes from its material and winding alone: equal for every model drawn with them."""

    material: Material
    variant: ShaderVariant
    pipeline: ScenePipeline
    sampled: tuple
    samplers: tuple
    factors: tuple
    label: str


def _shading(mat: Material, target: PipelineTarget, srgb_output: str | None, knobs: Knobs,
             anisotropy_adapter: str | None, notes: list[str] | None, directional: list[int], point: list[int],
             out: SceneDraws, mirror: bool, environment=None) -> _Shading:
    """A material's variant, pipeline, textures and samplers (registered in ``out``): a scene material samples
    every texture with its one sampler, a file material each with its own."""
    label = material_label(mat)
    variant = material_variant(mat, directional, point, srgb_output, notes if notes is not None else [], environment)
    out.variants.setdefault(variant.key, variant)
    pipeline = target.pipeline(variant, mat, mirror)
    out.pipelines.setdefault(pipeline.key, pipeline)
    sampled = tuple((f, getattr(mat, f)) for f in TEXTURE_FEATURES if f in variant.flags)
    spec = material_sampler(mat, label, knobs, anisotropy_adapter, notes) if sampled else None
    own = []
    for feature, feature_spec in file_materials.texture_samplers(mat, sampled, spec):
        if feature_spec is not spec:  # a file texture's own sampler: the anisotropy rule applies to it too
            feature_spec = material_sampler(mat, label, knobs, anisotropy_adapter, notes, feature_spec)
        own.append((feature, feature_spec))
    for feature, path in sampled:
        out.table.add_textures(label, ((feature, path),), file_materials.texture_mipmaps(mat, feature))
    for feature, feature_spec in own:
        out.table.add_sampler(feature_spec, label if not mat.texture_samplers else f"{label} {feature}")
    return _Shading(mat, variant, pipeline, sampled, tuple(own), tuple(draw_factors(mat, variant).items()), label)


def _plan_draw(model: Model, shading: _Shading) -> Draw:
    """The draw of one model with one material's shading."""
    mat, own = shading.material, shading.samplers
    draw_label = model.label if mat.part is None else f"{model.label} {mat.name.removeprefix(model.label).strip()}"
    return Draw(model.index, model.path, draw_label, mat.name, shading.variant.key, shading.pipeline.key,
                shading.sampled, own[0][1] if own else None, model.transform.matrix, shading.label, shading.factors,
                part=mat.part, samplers=own, topology=mat.topology, pose=model.pose)
