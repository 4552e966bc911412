"""The render plan's data: frozen dataclasses with no GPU objects (attachments, passes, variants, pipelines, knobs).

:mod:`.build` makes a :class:`RenderPlan` from a scene; :mod:`.explain` prints it.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wgpurender.core.course.effects import EffectStep
from wgpurender.core.course.formats import BYTES_PER_PIXEL, HDR_FORMAT, POST_PATHS, SAMPLE_COUNTS  # re-exported
from wgpurender.core.errors import UserError
from wgpurender.core.models.gltf_geometry import MAX_UV_SLOTS
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.core.plan.culling import CULLING
from wgpurender.core.plan.explain import explain
from wgpurender.core.plan.gl_facts import glsl_allows
from wgpurender.core.plan.instance_data import INSTANCE_DATA
from wgpurender.core.plan.mesh_loading import MESH_WORKERS
from wgpurender.core.scene import Placements, Scene

DEPTH_FORMAT = "depth32float"
LDR_SCENE_FORMAT = "rgba8unorm-srgb"  # 8-bit scene image for a post chain: shaders still see linear values
PLAN_OUTPUT_FORMATS = ("rgba8unorm-srgb", "rgba8unorm", "rgba16float", "bgra8unorm-srgb", "bgra8unorm")
DEPTH_FORMATS = ("depth32float", "depth24plus")
SCENE_FORMATS = ("rgba8unorm-srgb", "rgba16float", "rgba32float")
IMMEDIATES = ("auto", "on", "off")
# The post chain's intermediate images (knob post_intermediate): "auto" keeps the scene image's format (today's
# image); rgba8unorm stores the tone-mapped values in 8 bits, linear (half the bytes of rgba16float), and
# rgba8unorm-srgb sRGB-encoded (on the compute path through a scratch copy: it is not a storage format).
# "none" stores nothing before FXAA: the per-pixel effects before it are recomputed for every texel it reads.
POST_INTERMEDIATES = ("auto", "rgba16float", "rgba8unorm", "rgba8unorm-srgb", "none")
PLAN_FEATURES = ("immediates", "indirect-first-instance")  # the adapter features a plan reads (the rest: none)
# Formats a compute pass can write (storage textures); the -srgb ones cannot be (facts.md), bgra8unorm only with
# the "bgra8unorm-storage" feature, which the renderer does not ask for.
STORAGE_FORMATS = ("rgba8unorm", "rgba16float", "rgba32float")
# An output format that cannot be a storage texture -> the storage format holding the same bytes once the shader
# applies the sRGB curve. A compute pass writes such an offscreen output as its twin (no copy); wgpu-py 0.32 has no
# texture ``view_formats`` (create_texture raises NotImplementedError), so an -srgb view of one texture is not offered.
STORAGE_TWINS = {"rgba8unorm-srgb": "rgba8unorm"}
ATTACHMENT_ORDER = ("msaa-color", "depth", "scene-color", "post-intermediate", "post-mask", "post-scratch",
                    "output")  # the order passes use them

# Feature -> vertex attribute it needs (position is always there).
TEXTURE_FEATURES = ("albedo_map", "normal_map", "roughness_map", "emissive_map", "occlusion_map", "clearcoat_map",
                    "clearcoat_roughness_map", "clearcoat_normal_map")
EXTRA_UV_SLOTS = MAX_UV_SLOTS - 1  # coordinate slots beyond the first (vertex attributes uv1..uv4)
TANGENT_FEATURES = frozenset({"normal_map", "clearcoat_normal_map"})  # the maps that need the tangent frame
ATTRIBUTES = (("lighting", "normal"), ("uv", "uv"), ("tangent", "tangent"), ("vertex_color", "color"),
              *((f"uv{k}", f"uv{k}") for k in range(1, EXTRA_UV_SLOTS + 1)))
# "<texture feature>_uv<k>": that texture samples the mesh's coordinate slot k (vertex attribute uv<k>)
UV_SLOT_FLAGS = {f"{feature}_uv{k}": (feature, k) for feature in TEXTURE_FEATURES for k in range(1, EXTRA_UV_SLOTS + 1)}


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

    # Cached (the variant is frozen): a scene of 10k draws asks each draw's key and attributes several times.
    @functools.cached_property
    def features(self) -> frozenset[str]:
        """Flags plus ``name:N`` for each light count, e.g. {"lighting", "point_lights:2"}."""
        return self.flags | {f"{name}:{n}" for name, n in self.counts}

    @functools.cached_property
    def key(self) -> str:
        """Stable text key, e.g. ``albedo_map+lighting+normal_map+point_lights:2``; ``base`` when empty."""
        return "+".join(sorted(self.features)) or "base"

    @functools.cached_property
    def vertex_attributes(self) -> tuple[str, ...]:
        uses_uv = bool(self.flags & set(TEXTURE_FEATURES))
        slots = {f"uv{UV_SLOT_FLAGS[f][1]}" for f in self.flags if f in UV_SLOT_FLAGS}
        tangent = {"tangent"} if self.flags & TANGENT_FEATURES else set()
        have = self.flags | ({"uv"} if uses_uv else set()) | slots | tangent
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
    blend: bool = False  # alpha blending (glTF alphaMode BLEND): source-over, no depth writes
    topology: str = "triangle-list"  # "line-list" / "point-list": glTF lines and points
    culled: bool = False  # instances culled on the GPU, drawn indirectly through a visible list (core/plan/culling)

    @functools.cached_property
    def key(self) -> str:
        depth = f"{self.depth_format} {self.depth_compare}" if self.depth_format else "no-depth"
        winding = " | front face cw (mirrored model)" if self.front_face == "cw" else ""
        culling = " | double-sided (no culling)" if self.cull_mode == "none" else ""
        blending = " | alpha blend, no depth write" if self.blend else ""
        frustum = " | GPU frustum culling" if self.culled else ""
        shape = f" | {self.topology}" if self.topology != "triangle-list" else ""
        return (f"{self.variant.key} | {self.color_format} x{self.sample_count} | {depth}{winding}{culling}"
                f"{blending}{shape}{frustum}")


@dataclass(frozen=True)
class TextureUse:
    """A texture file to upload, the format it is uploaded as, and who samples it.

    ``size`` is read from the image's header (None when it cannot be read: the upload says why);
    ``mip_levels``: the levels the upload fills (1 without mipmaps; None when the size is unknown)."""

    path: Path
    format: str
    mipmaps: bool
    used_by: tuple[str, ...]
    size: tuple[int, int] | None = None
    mip_levels: int | None = 1


@dataclass(frozen=True)
class SamplerUse:
    spec: object  # wgpurender.wgpu_path.device.textures.SamplerSpec (frozen, hashable)
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
    part: int | None = None  # the model file's material whose triangles this draws (-1: none); None: all of them
    samplers: tuple[tuple[str, object], ...] = ()  # (feature, SamplerSpec): each texture's own sampler
    topology: str = "triangle-list"  # which of the part's primitives: triangles, or glTF lines / points
    worlds: Placements | None = None  # every instance's world matrix when the draw is instanced (core/plan/batches)
    first_instance: int = 0  # where its instances start in the scene's one Object storage buffer
    batch: str = ""  # why these instances are one draw (explain)
    cpu_culled: bool = False  # its instances are frustum-culled on the CPU (core/plan/culling.cpu_culled)
    pose: object | None = None  # the model's glTF animation pose (core/models/gltf_animation.Pose), None: at rest

    @property
    def mesh_key(self) -> tuple:
        """What names the vertices a draw reads: its model file, and the pose it is drawn in."""
        return (self.model_path, self.pose)

    @property
    def instance_count(self) -> int:
        return 1 if self.worlds is None else self.worlds.count

    def world_matrices(self) -> np.ndarray:
        """(instance_count, 4, 4) float64 world matrices: ``worlds``, or the one ``transform``."""
        if self.worlds is None:
            return np.array(self.transform, dtype=np.float64)[None]
        return self.worlds.array().astype(np.float64)

    def material_key(self) -> tuple:
        """Draws with equal keys read the same material: they share one material bind group / descriptor set."""
        return (self.variant_key, self.textures, self.samplers, self.sampler, self.factors)

    def material_identity(self) -> tuple:
        """:meth:`material_key`'s parts by identity: equal for draws whose parts are the same objects (every draw
        of one material and winding: the plan shares them, core/plan/draws._Shading); cheap to hash, where
        hashing the key itself walks its textures, samplers and factors (:func:`material_numbers`)."""
        return (self.variant_key, id(self.textures), id(self.samplers), id(self.sampler), id(self.factors))

    def sampler_of(self, feature: str) -> object | None:
        """The sampler a texture is sampled with (its own, else the draw's one sampler)."""
        return dict(self.samplers).get(feature, self.sampler)

    def factors_text(self) -> str:
        def show(v) -> str:
            return "(" + ", ".join(f"{x:g}" for x in v) + ")" if isinstance(v, tuple) else f"{v:g}"

        return ", ".join(f"{k}={show(v)}" for k, v in self.factors)



def material_numbers(draws) -> tuple[list[int], dict[tuple, int]]:
    """Each draw's material as a number (first use order), equal exactly where :meth:`Draw.material_key` is equal,
    and {key: number}. Each key is hashed once per :meth:`Draw.material_identity`, not once per draw: at 10k
    draws the keys' field-by-field hashes (sampler specs, texture paths, factors) were ~5 us a draw (issue 31.3)."""
    by_identity: dict[tuple, int] = {}
    numbers: dict[tuple, int] = {}
    out = []
    for d in draws:
        identity = d.material_identity()
        number = by_identity.get(identity)
        if number is None:
            number = by_identity[identity] = numbers.setdefault(d.material_key(), len(numbers))
        out.append(number)
    return out, numbers

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
    ``twin_of``: the pass writes the offscreen output itself in ``output_format`` (:data:`STORAGE_TWINS`),
    sRGB-encoded in the shader, so it holds the bytes a ``twin_of`` texture would: no scratch, no copy.
    ``bytes_read`` / ``bytes_written``: the compulsory memory traffic, each texel read once and written once.
    ``shape``: a compute pass's dispatch shape and ``shape_why`` the rule that chose it (core/plan/dispatch.py).
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
    copy_format: str | None = None  # the format of ``copy_to`` (the scratch is written in ``output_format``)
    twin_of: str | None = None  # the format whose bytes ``output_format`` holds (an -srgb output written directly)
    prelude: int = 0  # the first steps, applied to every texel the neighbourhood step reads (post_intermediate none)
    shape: tuple[int, int, int] | None = None  # compute: workgroup (x, y), rows per invocation (core/plan/dispatch.py)
    shape_why: str = ""
    tile: str = ""  # compute: FXAA reads through a workgroup tile: "texels" (the plan, a prelude), "luma" (bench)

    @property
    def encodes_for(self) -> str | None:
        """The format whose encoding the written bytes must have, when it is not ``output_format``."""
        return self.copy_format or self.twin_of

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
    device's enabled features (the plan reads "immediates"); ``backend``: the API under the adapter as wgpu
    reports it ("Vulkan", "OpenGL", ...; "WebGPU" for a browser), since some features are advertised where
    they cannot be trusted (wgpurender/core/plan/post.py, ``UNTRUSTED_IMMEDIATES``). ``storage``: the device
    offers storage buffers (``max-storage-buffers-per-shader-stage`` > 0; core/plan/instance_data.py);
    ``compute``: it runs compute shaders (``max-compute-invocations-per-workgroup`` > 0; core/plan/culling.py).
    Both are core Vulkan (and WebGPU); GLES 3.0 and a GL context below 4.3 have neither.
    """

    adapter_type: str
    features: frozenset[str] = frozenset()
    name: str = ""
    backend: str = ""
    storage: bool = True
    compute: bool = True
    # the device's max-storage-buffer-binding-size (Vulkan: maxStorageBufferRange; core/plan/instance_data.fit_binding),
    # None where not known; not compared: wgpu may bind less than Vulkan's range, and one device's facts are equal
    max_storage_binding: int | None = field(default=None, compare=False)

    @classmethod
    def of(cls, adapter_type: str, features: Iterable[str] = (), name: str = "", backend: str = "",
           limits: dict | None = None, gl_version: str = "") -> AdapterFacts:
        """The facts from what a device reports: its type as wgpu names it ("DiscreteGPU", "IntegratedGPU",
        "CPU", ...), the features a plan reads (:data:`PLAN_FEATURES`; others are dropped, so the wgpu and the raw
        path's facts of one device are equal), its name, the API under it ("Vulkan", "OpenGL", ...) and its
        limits by WebGPU name (None: a core-Vulkan device, which has storage buffers and compute); ``gl_version``:
        an OpenGL adapter's version string, whose GLSL version naga must support both (gl_facts.glsl_allows)."""
        limits = limits or {}
        return cls(adapter_type, frozenset(f for f in features if f in PLAN_FEATURES), name, backend,
                   storage=limits.get("max-storage-buffers-per-shader-stage", 1) > 0
                   and glsl_allows("storage", gl_version),
                   compute=limits.get("max-compute-invocations-per-workgroup", 1) > 0
                   and glsl_allows("compute", gl_version),
                   max_storage_binding=limits.get("max-storage-buffer-binding-size"))

    def accuracy_size(self, preset: str) -> tuple[int, int]:
        """The base size ``bench accuracy`` times at on this adapter (core/plan/bench_size.py says why)."""
        from wgpurender.core.plan.bench_size import accuracy_size

        return accuracy_size(self.adapter_type, preset)


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
    output_storage: bool = True  # the output texture may be a storage texture (offscreen: yes; a swapchain: no)
    anisotropy: str = DEFAULT_ANISOTROPY  # the anisotropy rule (wgpurender/core/plan/anisotropy.py), for ``adapter``
    culling: str = "auto"  # "auto", "gpu", "cpu" or "off": which instanced draws are culled (core/plan/culling.py)
    instance_data: str = "auto"  # "auto", "storage" or "vertex": how instances reach the vertex shader
    post_intermediate: str = "auto"  # POST_INTERMEDIATES: the format between post passes (a quality knob)
    mesh_workers: str = "auto"  # "auto", "off" or "on": model files read by worker processes (plan/mesh_loading.py)

    def check(self) -> None:
        bad = [(name, value, allowed) for name, value, allowed in (
            ("depth_format", self.depth_format, DEPTH_FORMATS), ("post_path", self.post_path, (None, *POST_PATHS)),
            ("immediates", self.immediates, IMMEDIATES), ("scene_format", self.scene_format, (None, *SCENE_FORMATS)),
            ("culling", self.culling, CULLING), ("instance_data", self.instance_data, INSTANCE_DATA),
            ("post_intermediate", self.post_intermediate, POST_INTERMEDIATES),
            ("mesh_workers", self.mesh_workers, MESH_WORKERS),
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
    # the glTF models the window animates (core/scene/playback.Track each; empty: a still scene, nothing per frame)
    playing: tuple = ()
    knobs: Knobs = field(default_factory=Knobs)
    settings: tuple[tuple[str, str, str], ...] = ()  # (knob, resolved value, why), what explain() shows
    msaa_asked: int = 0  # the msaa the scene or the caller asked for (``msaa`` is what is drawn: 1 with no models)
    absent: tuple[tuple[str, str], ...] = ()  # (what a renderer could have made but does not, why), explain() shows
    scene: Scene | None = field(default=None, repr=False, compare=False)
    rebuild: Callable[..., RenderPlan] | None = field(default=None, repr=False, compare=False)  # resolve.resolve_knobs

    # -- knobs -----------------------------------------------------------------
    def with_knobs(self, **changes) -> RenderPlan:
        """The plan of the same scene with knobs changed: any :class:`Knobs` field, or ``size``,
        ``output_format``, ``msaa`` (the CLI's overrides). This is how a benchmark or a renderer asks for a
        knob: the result is a whole new plan, resolved again by :func:`~wgpurender.core.plan.resolve.resolve_plan`
        (``rebuild``), so ``explain()`` stays true."""
        overrides = {k: changes.pop(k) for k in ("size", "output_format", "msaa") if k in changes}
        unknown = sorted(set(changes) - set(Knobs.__dataclass_fields__))
        if unknown:
            raise UserError(f"unknown plan knob {unknown[0]!r}: knobs are "
                            f"{', '.join(Knobs.__dataclass_fields__)}, size, output_format, msaa")
        if self.scene is None or self.rebuild is None:
            raise UserError("this plan was not resolved from a scene: resolve it with resolve_plan(scene, adapter)")
        current = {"size": self.size, "output_format": self.output_format, "msaa": self.msaa_asked or self.msaa}
        return self.rebuild(self.scene, dataclasses.replace(self.knobs, **changes), **{**current, **overrides})

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
        """Formats of the textures that get mip chains: one mip-generation render pipeline each (mipmap.wgsl).
        A 1x1 image has no level to fill: it needs none."""
        return tuple(dict.fromkeys(t.format for t in self.textures if t.mipmaps and (t.mip_levels or 2) > 1))

    @property
    def objects(self) -> tuple:
        """Every object the wgpu renderer creates for this plan, by device call (wgpurender/core/plan/objects.py)."""
        from wgpurender.core.plan.objects import gpu_objects  # objects.py does not import this module (no cycle)

        return gpu_objects(self)

    def object_counts(self) -> dict[str, int]:
        """How many objects of each kind (device call) the renderer creates: what the plan test compares."""
        counts: dict[str, int] = {}
        for o in self.objects:
            counts[o.kind] = counts.get(o.kind, 0) + o.count
        return counts

    @property
    def uses_ibl(self) -> bool:
        """A draw shades with image-based lighting (an ``ibl`` variant): the maps' buffer exists."""
        return any("ibl" in v.flags for v in self.variants) and bool(self.scene_pass.draws)

    @property
    def buffers(self) -> tuple[tuple[str, str], ...]:
        """(buffer, what it holds) for every GPU buffer the renderer makes for this plan (readback aside)."""
        draws = self.scene_pass.draws
        out = []
        if draws:
            out.append(("scene-camera", "uniform: Camera (view, projection, eye, lights), written when they change"))
            instances = sum(d.instance_count for d in draws)
            read = ("storage: {n} Object block(s), one per instance, read at instance_index (128 bytes each)"
                    if self.instance_data == "storage" else "vertex (step mode instance): {n} Object block(s), one "
                    "per instance, read as instance attributes (128-byte stride)")
            out.append(("scene-objects", read.format(n=instances)))
            culled = self.culled_draws
            if culled:
                n = sum(d.instance_count for d in culled)
                out.append(("scene-visible", f"storage: the visible instances' indices, up to {n} (GPU culling)"))
                out.append(("scene-indirect", f"indirect: {len(culled)} draw_indexed_indirect argument block(s), "
                                              "instance_count written by the culling pass"))
                out.append(("scene-cull", f"uniform: {len(culled)} Cull block(s) (frustum planes, the mesh's "
                                          "bounding sphere, the instance range)"))
            if self.immediates is not True:
                when = "no immediates" if self.immediates is False else "only if the device lacks immediates"
                materials = len({d.material_key() for d in draws})
                out.append(("scene-materials", f"uniform: {materials} Material slice(s), one per distinct material "
                                               f"({when})"))
        meshes = dict.fromkeys((d.mesh_key, self.variant(d.variant_key).vertex_attributes) for d in draws)
        if meshes:  # every mesh in one pair, each at its own offset (wgpu_path/scene/resources.py upload_meshes)
            layouts = "; ".join(dict.fromkeys(", ".join(attributes) for _, attributes in meshes))
            names = ", ".join(dict.fromkeys(key[0].name for key, _ in meshes))
            out.append(("scene-vertices", f"vertex: {len(meshes)} mesh(es) ({names}), each interleaved at its own "
                                          f"offset (attributes {layouts}); more such buffers where one would pass the "
                                          "device's max-buffer-size"))
            out.append(("scene-indices", f"index: the same {len(meshes)} mesh(es), each at its own offset"))
        if self.uses_ibl:
            from wgpurender.core.course import ibl_maps

            env = self.scene.environment if self.scene is not None else None
            source = f" of [environment] {env.label}, {env.samples} GGX samples" if env is not None else ""
            out.append(("scene-ibl", f"storage: image-based lighting maps{source} ({ibl_maps.packed_bytes()} bytes: "
                        f"irradiance {'x'.join(map(str, ibl_maps.IRRADIANCE_SIZE))}, {ibl_maps.LEVELS} prefiltered "
                        f"levels {'x'.join(map(str, ibl_maps.PREFILTER_SIZE))}, BRDF table {ibl_maps.LUT_SIZE}^2; "
                        "made on the GPU by compute passes, ibl.wgsl / ibl.comp), for the ibl variant(s)"))
            out.append(("scene-ibl-environment", "storage: the environment's radiance the compute passes read "
                                                 "(averaged down to at most "
                                                 f"{'x'.join(map(str, ibl_maps.MAX_ENVIRONMENT))})"))
            out.append(("scene-ibl-params", f"uniform: {len(ibl_maps.PASSES)} Params blocks (sizes, samples), one "
                                            "per compute pass, 256 bytes apart"))
        for p in self.post_passes:
            if any(s.spec.params for s in p.steps):
                out.append((f"post-{p.effect}-params", "uniform: PassParams (generated from the effect specs)"))
        return tuple(out)

    @property
    def ibl_passes(self) -> tuple[str, ...]:
        """The compute passes that make the image-based lighting maps (core/course/ibl_maps.PASSES), if used."""
        if not self.uses_ibl:
            return ()
        from wgpurender.core.course import ibl_maps

        return ibl_maps.PASSES

    @property
    def culled_draws(self) -> tuple[Draw, ...]:
        """The draws whose instances the GPU culls each frame (core/plan/culling.py)."""
        culled = {p.key for p in self.pipelines if p.culled}
        return tuple(d for d in self.scene_pass.draws if d.pipeline_key in culled)

    @property
    def cpu_culled_draws(self) -> tuple[Draw, ...]:
        """The draws whose instances the CPU culls when the camera moves (core/plan/culling.py)."""
        return tuple(d for d in self.scene_pass.draws if d.cpu_culled)

    @property
    def instance_data(self) -> str:
        """"storage" or "vertex": how instances reach the vertex shader (core/plan/instance_data.py)."""
        return self.setting("instance_data")

    @property
    def mesh_workers(self) -> int:
        """Worker processes that read the model files (0: this process reads them; core/plan/mesh_loading.py)."""
        return int(self.setting("mesh_workers"))

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
    def target_format(self) -> str:
        """The format of the output texture the renderer writes and reads back: ``output_format``, or the
        storage twin a compute post pass writes directly (the same bytes: :data:`STORAGE_TWINS`)."""
        return self.attachment("output").format

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
        return self._by_key[1][key]

    def variant(self, key: str) -> ShaderVariant:
        return self._by_key[0][key]

    @functools.cached_property
    def _by_key(self) -> tuple[dict[str, ShaderVariant], dict[str, ScenePipeline]]:
        """Variants and pipelines by key, first of each key (a renderer asks for them per draw: 10k draws)."""
        variants: dict[str, ShaderVariant] = {}
        pipelines: dict[str, ScenePipeline] = {}
        for v in self.variants:
            variants.setdefault(v.key, v)
        for p in self.pipelines:
            pipelines.setdefault(p.key, p)
        return variants, pipelines

    # -- text ----------------------------------------------------------------
    def explain(self) -> str:
        """Passes, attachments, pipelines, textures, samplers and knobs, each with what asked for it."""
        return explain(self)


__all__ = [
    "ATTACHMENT_ORDER",
    "ATTRIBUTES",
    "AdapterFacts",
    "Attachment",
    "BYTES_PER_PIXEL",
    "DEPTH_FORMAT",
    "DEPTH_FORMATS",
    "Draw",
    "HDR_FORMAT",
    "IMMEDIATES",
    "Knobs",
    "LDR_SCENE_FORMAT",
    "PLAN_OUTPUT_FORMATS",
    "POST_INTERMEDIATES",
    "POST_PATHS",
    "PostPass",
    "PostPipeline",
    "RenderPlan",
    "SAMPLE_COUNTS",
    "SCENE_FORMATS",
    "STORAGE_FORMATS",
    "STORAGE_TWINS",
    "SamplerUse",
    "ScenePass",
    "ScenePipeline",
    "ShaderVariant",
    "TEXTURE_FEATURES",
    "TextureUse",
]
