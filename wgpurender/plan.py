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

import dataclasses
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

from .course.effects import EffectStep, group_passes, step_notes, steps_for_target
from .course.shading import material_factors
from .errors import UserError
from .scene import Material, Scene, load_scene

DEPTH_FORMAT = "depth32float"
HDR_FORMAT = "rgba16float"
LDR_SCENE_FORMAT = "rgba8unorm-srgb"  # 8-bit scene image for a post chain: shaders still see linear values
COLOR_TEXTURE_FORMAT = "rgba8unorm-srgb"  # albedo: sRGB-encoded image, decoded by the sampler
DATA_TEXTURE_FORMAT = "rgba8unorm"  # normal and roughness maps: values used as stored
PLAN_OUTPUT_FORMATS = ("rgba8unorm-srgb", "rgba8unorm", "rgba16float", "bgra8unorm-srgb", "bgra8unorm")
SAMPLE_COUNTS = (1, 4)
DEPTH_FORMATS = ("depth32float", "depth24plus")
SCENE_FORMATS = ("rgba8unorm-srgb", "rgba16float", "rgba32float")
POST_PATHS = ("auto", "fragment", "compute")
IMMEDIATES = ("auto", "on", "off")
# Formats a compute pass can write (storage textures); the -srgb ones cannot be (facts.md), bgra8unorm only with
# the "bgra8unorm-storage" feature, which the renderer does not ask for.
STORAGE_FORMATS = ("rgba8unorm", "rgba16float", "rgba32float")
BYTES_PER_PIXEL = {"rgba8unorm": 4, "rgba8unorm-srgb": 4, "bgra8unorm": 4, "bgra8unorm-srgb": 4, "rgba16float": 8,
                   "rgba32float": 16, "depth16unorm": 2, "depth24plus": 4, "depth32float": 4}
ATTACHMENT_ORDER = ("msaa-color", "depth", "scene-color", "post-intermediate", "post-mask", "post-scratch",
                    "output")  # the order passes use them

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
    depth_compare: str = "less"

    @property
    def key(self) -> str:
        depth = f"{self.depth_format} {self.depth_compare}" if self.depth_format else "no-depth"
        winding = " | front face cw (mirrored model)" if self.front_face == "cw" else ""
        return f"{self.variant.key} | {self.color_format} x{self.sample_count} | {depth}{winding}"


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
    factors: tuple[tuple[str, object], ...] = ()  # the per-draw Material values (course.shading.material_factors)

    def factors_text(self) -> str:
        def show(v) -> str:
            return "(" + ", ".join(f"{x:g}" for x in v) + ")" if isinstance(v, tuple) else f"{v:g}"

        return ", ".join(f"{k}={show(v)}" for k, v in self.factors)


@dataclass(frozen=True)
class ScenePass:
    """The pass that draws the models: into ``color`` (resolved into ``resolve_target`` when multisampled)."""

    color: str
    resolve_target: str | None
    depth: str | None
    clear_color: tuple[float, float, float, float]
    draws: tuple[Draw, ...]
    depth_clear: float = 1.0
    kind: str = "scene"

    @property
    def writes(self) -> str:
        return self.resolve_target or self.color


@dataclass(frozen=True)
class PostPass:
    """One full-screen pass of the post chain: its effect ``steps`` run as one shader, ``input`` -> ``output``.

    Several steps share a pass when the plan fuses them (each reads only the pixel the one before it
    wrote); ``fusion`` says why. ``path`` is "fragment" (a render pass drawing a full-screen triangle) or
    "compute" (a dispatch writing a storage texture). ``mask``: FXAA's depth mask on the fragment path.
    ``copy_to``: a compute pass whose output format cannot be a storage texture writes ``output`` (a
    scratch rgba8unorm, sRGB-encoded in the shader) and is then copied into ``copy_to``.
    ``bytes_read`` / ``bytes_written``: the compulsory memory traffic, each texel read once and written once.
    """

    index: int
    steps: tuple[EffectStep, ...]
    input: str
    output: str
    input_format: str
    output_format: str
    path: str = "fragment"
    fusion: str = ""
    notes: tuple[str, ...] = ()
    mask: str | None = None
    copy_to: str | None = None
    bytes_read: int = 0
    bytes_written: int = 0
    kind: str = "post"

    @property
    def effect(self) -> str:
        """The steps' names joined with "+", e.g. ``tonemap+vignette`` (one name when not fused)."""
        return "+".join(s.effect for s in self.steps)

    @property
    def params(self) -> tuple[tuple[str, float | str], ...]:
        """The parameters of a single-step pass (``effect.name`` keys when fused)."""
        if len(self.steps) == 1:
            return self.steps[0].params
        return tuple((f"{s.effect}.{k}", v) for s in self.steps for k, v in s.params)

    @property
    def reason(self) -> str:
        return "; ".join(s.asked_by for s in self.steps)

    @property
    def fused(self) -> bool:
        return len(self.steps) > 1

    @property
    def writes(self) -> str:
        return self.copy_to or self.output

    @property
    def bytes_moved(self) -> int:
        return self.bytes_read + self.bytes_written


@dataclass(frozen=True)
class PostPipeline:
    """A pipeline of a post pass: ``stage`` "fragment" (with ``entry_point`` and an optional depth test) or
    "compute"; ``target_format``: the colour attachment's or the storage texture's format."""

    effects: str
    stage: str
    entry_point: str
    target_format: str
    depth_format: str | None = None

    @property
    def key(self) -> str:
        depth = f", depth {self.depth_format}" if self.depth_format else ""
        return f"{self.effects} {self.stage} {self.entry_point} -> {self.target_format}{depth}"


@dataclass(frozen=True)
class AdapterFacts:
    """What the plan needs to know about an adapter for its "auto" knobs (no GPU object: plain values).

    ``adapter_type`` as wgpu reports it ("DiscreteGPU", "IntegratedGPU", "CPU", ...); ``features``: the
    device's enabled features (the plan reads "immediates").
    """

    adapter_type: str
    features: frozenset[str] = frozenset()
    name: str = ""


@dataclass(frozen=True)
class Knobs:
    """Every choice a renderer or benchmark may make beyond the scene file; each is shown by ``explain()``.

    ``None`` means "the scene's own setting" (render.post_fuse, render.post_path, the scene format that
    render.hdr and the chain ask for). Change them with :meth:`RenderPlan.with_knobs`.
    """

    depth_format: str = DEPTH_FORMAT
    reverse_z: bool = False
    scene_format: str | None = None
    post_fuse: bool | None = None
    post_path: str | None = None
    immediates: str = "auto"
    adapter: AdapterFacts | None = None

    def check(self) -> None:
        bad = [(name, value, allowed) for name, value, allowed in (
            ("depth_format", self.depth_format, DEPTH_FORMATS), ("post_path", self.post_path, (None, *POST_PATHS)),
            ("immediates", self.immediates, IMMEDIATES), ("scene_format", self.scene_format, (None, *SCENE_FORMATS)),
        ) if value not in allowed]
        for name, value, allowed in bad:
            raise UserError(f"plan knob {name} = {value!r}: choose one of "
                            f"{', '.join(str(a) for a in allowed if a is not None)}")


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
    post_pipelines: tuple[PostPipeline, ...]
    textures: tuple[TextureUse, ...]
    samplers: tuple[SamplerUse, ...]
    camera_note: str = ""
    notes: tuple[str, ...] = field(default=())
    knobs: Knobs = field(default_factory=Knobs)
    settings: tuple[tuple[str, str, str], ...] = ()  # (knob, resolved value, why), what explain() shows
    scene: Scene | None = field(default=None, repr=False, compare=False)

    # -- knobs -----------------------------------------------------------------
    def with_knobs(self, **changes) -> RenderPlan:
        """The plan of the same scene with knobs changed: any :class:`Knobs` field, or ``size``,
        ``output_format``, ``msaa`` (the CLI's overrides). This is how a benchmark or a renderer asks for a
        knob: the result is a whole new plan, so ``explain()`` stays true."""
        overrides = {k: changes.pop(k) for k in ("size", "output_format", "msaa") if k in changes}
        unknown = sorted(set(changes) - set(Knobs.__dataclass_fields__))
        if unknown:
            raise UserError(f"unknown plan knob {unknown[0]!r}: knobs are "
                            f"{', '.join(Knobs.__dataclass_fields__)}, size, output_format, msaa")
        if self.scene is None:
            raise UserError("this plan was not built from a scene: build it with build_plan(scene, ...)")
        current = {"size": self.size, "output_format": self.output_format, "msaa": self.msaa}
        return build_plan(self.scene, **{**current, **overrides}, knobs=dataclasses.replace(self.knobs, **changes))

    def setting(self, name: str) -> str:
        """A resolved knob's value as text, e.g. ``setting("post_path") == "compute"``."""
        return next(value for knob, value, _ in self.settings if knob == name)

    @property
    def post_path(self) -> str:
        return self.setting("post_path")

    @property
    def immediates(self) -> bool | None:
        """True/False when decided (knob "on"/"off" or a known adapter), None: the renderer asks its device."""
        return {"on": True, "off": False}.get(self.setting("immediates").split()[0])

    @property
    def reverse_z(self) -> bool:
        return self.knobs.reverse_z

    @property
    def mipmap_formats(self) -> tuple[str, ...]:
        """Formats of the textures that get mip chains: one mip-generation render pipeline each (mipmap.wgsl)."""
        return tuple(dict.fromkeys(t.format for t in self.textures if t.mipmaps))

    @property
    def post_steps(self) -> tuple[EffectStep, ...]:
        """Every effect step of the chain in order, whatever the passes (what the raw path's subpass composes)."""
        return tuple(s for p in self.post_passes for s in p.steps)

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

    def pipeline(self, key: str) -> ScenePipeline:
        return next(p for p in self.pipelines if p.key == key)

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
        out.append("knobs:")
        for knob, value, why in self.settings:
            out.append(f"  {knob}: {value} <- {why}")
        out.append("")
        out.append("passes:")
        for i, p in enumerate(self.passes, start=1):
            out.extend(_explain_pass(i, p, self.size))
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
        out.append("post pipelines:" if self.post_pipelines else "post pipelines: none")
        out.extend(f"  {pl.key}" for pl in self.post_pipelines)
        out.append("")
        out.append("textures:" if self.textures else "textures: none")
        for t in self.textures:
            mips = "with mipmaps" if t.mipmaps else "no mipmaps"
            shown = os.path.relpath(t.path, self.scene_path.parent)
            out.append(f"  {shown} as {t.format}, {mips} <- {'; '.join(t.used_by)}")
        if self.mipmap_formats:
            out.append("mipmap pipelines: " + ", ".join(self.mipmap_formats)
                       + " (one render pipeline per format generates every mip chain of that format)")
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


def _megabytes(n: int) -> str:
    return f"{n / 1e6:.1f} MB"


def _explain_pass(number: int, p: ScenePass | PostPass, size: tuple[int, int]) -> list[str]:
    if isinstance(p, ScenePass):
        into = f"{p.color} resolved into {p.resolve_target}" if p.resolve_target else p.color
        depth = f", depth attachment {p.depth}" if p.depth else ""
        clear = ", ".join(f"{c:g}" for c in p.clear_color)
        lines = [f"  {number}. scene: draw {len(p.draws)} model(s) into {into}{depth}, clear ({clear})"]
        for d in p.draws:
            lines.append(f"       {d.label}: {d.material_label}, variant {d.variant_key}")
            lines.append(f"         material factors: {d.factors_text()}")
        return lines
    steps = " + ".join(s.label() for s in p.steps)
    into = f"{p.output} ({p.output_format})" + (f", copied into {p.copy_to}" if p.copy_to else "")
    lines = [f"  {number}. post [{p.path}] {steps}: {p.input} ({p.input_format}) -> {into}"]
    lines.extend(f"       <- {s.asked_by}" for s in p.steps)
    if p.fusion:
        lines.append(f"       fused: {p.fusion}")
    if p.mask:
        lines.append(f"       mask: {p.mask} (depth test skips blocks without an edge pixel)")
    lines.append(f"       bytes: {_megabytes(p.bytes_read)} read + {_megabytes(p.bytes_written)} written = "
                 f"{_megabytes(p.bytes_moved)} at {size[0]}x{size[1]} (each texel once)")
    lines.extend(f"       note: {n}" for n in p.notes)
    return lines


# ---------------------------------------------------------------------------
# Building the plan
# ---------------------------------------------------------------------------


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


def _resolve_post_path(r, knobs: Knobs) -> tuple[str, str]:
    """fragment or compute, and why. The "auto" rule: compute on a discrete GPU (a fragment pass there is
    raster-bound, a compute pass uses every SM: facts.md on the H100/H200); fragment everywhere else (a CPU
    driver like lavapipe rasterises a full-screen triangle as cheaply as it runs a dispatch, and an
    integrated or mobile GPU's raster path is its fast path); fragment when the adapter is not known."""
    asked = knobs.post_path or r.post_path
    origin = "knob post_path" if knobs.post_path else f"render.post_path = {r.post_path}"
    if asked != "auto":
        return asked, origin
    adapter = knobs.adapter
    if adapter is None:
        return "fragment", f"{origin}, adapter not known yet: fragment (the renderer re-plans for its adapter)"
    if adapter.adapter_type == "DiscreteGPU":
        return "compute", f"{origin}: compute on a discrete GPU ({adapter.name or adapter.adapter_type})"
    return "fragment", f"{origin}: fragment on a {adapter.adapter_type} adapter ({adapter.name or 'unnamed'})"


def _resolve_immediates(knobs: Knobs) -> tuple[str, str]:
    if knobs.immediates != "auto":
        return knobs.immediates, "knob immediates"
    if knobs.adapter is None:
        return "auto", ("material factors pushed as immediates when the device offers the 'immediates' feature, "
                        "else read from a uniform buffer slice per draw")
    on = "immediates" in knobs.adapter.features
    return ("on" if on else "off"), ("the device offers 'immediates': material factors are pushed per draw" if on
                                     else "the device lacks 'immediates': material factors come from a uniform "
                                     "buffer slice per draw")


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


def _fusion_text(group: tuple[EffectStep, ...]) -> str:
    if len(group) < 2:
        return ""
    pixel = [s.effect for s in group if s.spec.fusable]
    head = group[0] if not group[0].spec.fusable else None
    verb = "reads only the pixel it writes" if len(pixel) == 1 else "each read only the pixel they write"
    runs = "it runs as a function" if len(pixel) == 1 else "they run as functions"
    why = f"{', '.join(pixel)} {verb}, so {runs} in one shader"
    if head is not None:
        why += f" on the pixel {head.effect} just computed ({head.effect} reads neighbours, so it starts the pass)"
    return why + f"; saves {len(group) - 1} write and read of the whole image"


def plan_post_passes(steps: list[EffectStep], fuse: bool, path: str, scene_target: str, scene_fmt: str, out_fmt: str,
                 size: tuple[int, int]) -> tuple[list[PostPass], list[Attachment]]:
    """The chain's passes and the attachments only they use (ping-pong intermediates, FXAA mask, scratch)."""
    groups = group_passes(steps, fuse)
    n = len(groups)
    temp_fmt = scene_fmt
    notes_all: list[str] = []
    if path == "compute" and scene_fmt not in STORAGE_FORMATS and n > 1:
        temp_fmt = HDR_FORMAT
        notes_all.append(f"{scene_fmt} cannot be a storage texture: the compute path's intermediates are {HDR_FORMAT}")
    temps = ["post_a", "post_b"][:min(max(n - 1, 0), 2)]
    attachments = []
    for i, name in enumerate(temps):
        users = [j for j in range(n - 1) if j % 2 == i]
        attachments.append(Attachment(name, "post-intermediate", temp_fmt, size, 1, (
            "written by " + ", ".join(f"post pass {j + 1} ({'+'.join(s.effect for s in groups[j])})" for j in users)
            + " and read by the next pass (ping-pong)",) + tuple(notes_all)))
    pixels = size[0] * size[1]
    passes = []
    for i, group in enumerate(groups):
        last = i == n - 1
        src_name = scene_target if i == 0 else temps[(i - 1) % 2]
        src_fmt = scene_fmt if i == 0 else temp_fmt
        dst_name, dst_fmt = ("output", out_fmt) if last else (temps[i % 2], temp_fmt)
        notes = [n for s in group for n in step_notes(s, src_fmt, dst_fmt)]
        pass_path, copy_to, mask = path, None, None
        if path == "compute" and dst_fmt not in STORAGE_FORMATS:
            if dst_fmt.startswith("rgba8"):
                copy_to, dst_name, dst_fmt = dst_name, "post_scratch", "rgba8unorm"
                notes.append(f"{copy_to} is {out_fmt}, which cannot be a storage texture: the shader writes "
                             "rgba8unorm with the sRGB curve applied, then the image is copied (same bytes)")
                attachments.append(Attachment("post_scratch", "post-scratch", "rgba8unorm", size, 1, (
                    f"post pass {i + 1} on the compute path writes it; copied into {copy_to}",)))
            else:
                pass_path = "fragment"
                notes.append(f"{dst_fmt} cannot be a storage texture: this pass stays a fragment pass")
        head = group[0].spec
        if pass_path == "fragment" and head.mask_format:
            mask = f"{head.name}_mask"
            attachments.append(Attachment(mask, "post-mask", head.mask_format, size, 1, (
                f"post pass {i + 1} {head.name}: draw 1 marks edge pixels in depth, draw 2 runs the full "
                f"{head.name} depth-tested on edges only (wgpurender/post/shaders.py says why)",)))
        read = pixels * BYTES_PER_PIXEL[src_fmt]
        written = pixels * BYTES_PER_PIXEL[dst_fmt]
        if mask:
            written += pixels * BYTES_PER_PIXEL[head.mask_format]
            read += pixels * BYTES_PER_PIXEL[head.mask_format]
        if copy_to:
            read += pixels * BYTES_PER_PIXEL[dst_fmt]
            written += pixels * BYTES_PER_PIXEL[out_fmt]
        passes.append(PostPass(i, group, src_name, dst_name, src_fmt, dst_fmt, pass_path, _fusion_text(group),
                               tuple(notes), mask, copy_to, read, written))
    return passes, attachments


def _post_pipelines(passes: list[PostPass]) -> tuple[PostPipeline, ...]:
    out: list[PostPipeline] = []
    for p in passes:
        if p.path == "compute":
            out.append(PostPipeline(p.effect, "compute", "cs_main", p.output_format))
        elif p.mask:
            depth = p.steps[0].spec.mask_format
            out.append(PostPipeline(p.effect, "fragment", "fs_mark", p.output_format, depth))
            out.append(PostPipeline(p.effect, "fragment", "fs_main", p.output_format, depth))
        else:
            out.append(PostPipeline(p.effect, "fragment", "fs_main", p.output_format))
    return tuple(dict.fromkeys(out))


def build_plan(scene: Scene, *, size: tuple[int, int] | None = None, output_format: str | None = None,
               msaa: int | None = None, knobs: Knobs | None = None) -> RenderPlan:
    """The plan for ``scene``; ``size``, ``output_format`` and ``msaa`` override [render] (CLI flags);
    ``knobs`` (:class:`Knobs`) make the choices a scene file does not (depth, post path, adapter...)."""
    _check_overrides(size, output_format, msaa)
    knobs = knobs or Knobs()
    knobs.check()
    r = scene.render
    size = tuple(size or r.size)
    out_fmt = output_format or r.output_format
    msaa = msaa or r.msaa
    src = lambda key, value: f"render.{key} = {value}" + (" (overridden)" if value != getattr(r, key) else "")  # noqa: E731
    notes: list[str] = []

    # -- knobs -------------------------------------------------------------------
    post_path, path_why = _resolve_post_path(r, knobs)
    fuse = r.post_fuse if knobs.post_fuse is None else knobs.post_fuse
    fuse_why = ("knob post_fuse" if knobs.post_fuse is not None else f"render.post_fuse = {str(r.post_fuse).lower()}")
    immediates, immediates_why = _resolve_immediates(knobs)
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
    post_passes, post_attachments = plan_post_passes(steps, fuse, post_path, scene_target, scene_fmt, out_fmt, size)
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
        mat = model.material
        first_time = id(mat) not in seen_materials
        seen_materials.add(id(mat))
        variant = material_variant(mat, directional, point, srgb_output, notes if first_time else [])
        variants.setdefault(variant.key, variant)
        # A mirroring world matrix (negative determinant) turns the winding around: its own pipeline.
        front_face = "cw" if _determinant3(model.transform.matrix) < 0 else "ccw"
        pipeline = ScenePipeline(variant, scene_fmt, msaa, knobs.depth_format, front_face=front_face,
                                 depth_compare=depth_compare)
        pipelines.setdefault(pipeline.key, pipeline)
        sampled = tuple((f, getattr(mat, f)) for f in TEXTURE_FEATURES if f in variant.flags)
        spec = mat.sampler.spec() if sampled else None
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
        factors = material_factors(tuple(mat.albedo_color), mat.roughness, "lighting" in variant.flags,
                                   "roughness_map" in variant.flags)
        draws.append(Draw(model.index, model.path, model.label, mat.name, variant.key, pipeline.key, sampled, spec,
                          model.transform.matrix, label, tuple(factors.items())))

    scene_pass = ScenePass(color_target, scene_target if msaa > 1 else None, "depth" if scene.models else None,
                           r.clear_color, tuple(draws), depth_clear=0.0 if knobs.reverse_z else 1.0)
    passes = [scene_pass, *post_passes]
    post_pipelines = _post_pipelines(post_passes)
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
    )


def plan_scene_file(path: str | Path, **overrides) -> RenderPlan:
    return build_plan(load_scene(path), **overrides)


def explain_scene(path: str | Path, adapter: AdapterFacts | None = None, **overrides) -> str:
    """The plan of a scene file as text (what ``render SCENE.toml --explain`` prints); with ``adapter``, the
    "auto" knobs are decided for it, as the renderer decides them, so the text lists what it would create."""
    plan = plan_scene_file(path, **overrides)
    return (plan.with_knobs(adapter=adapter) if adapter is not None else plan).explain()


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
