"""Scene files: TOML parsed and validated into frozen dataclasses.

A scene says what to draw (models, materials, lights, camera) and how to present
it (size, MSAA, HDR, post chain). :mod:`wgpurender.plan` turns a :class:`Scene`
into the passes and pipelines it needs. Full schema, with an example, in
docs/scenes.md; in short (every path is relative to the scene file's folder)::

    description = "optional text"

    [camera]                       # required
    eye = [0, 1, 3]                # required
    target = [0, 0, 0]             # required
    up = [0, 1, 0]
    fov_y = 45.0                   # degrees, vertical
    near = 0.1
    far = 100.0
    convention = "wgpu"            # or "glm-vulkan": see Camera

    [materials.brick]              # a named material (or inline: material = { ... } in a model)
    albedo_map = "textures/brick.png"      # sRGB colour texture
    albedo_color = [1, 1, 1]               # linear RGB(A); multiplies albedo_map
    normal_map = "textures/brick_n.png"    # tangent space, +Y up, linear
    roughness_map = "textures/brick_r.png" # linear, G channel (glTF layout)
    roughness = 0.5
    unlit = false
    uv_flip_v = false                      # v -> 1 - v, for meshes whose v = 0 is the bottom
    sampler = { filter = "linear", mipmaps = true, anisotropy = 1, address_mode = "repeat" }

    [[models]]                     # zero or more, drawn in order
    path = "models/cube.glb"       # .obj .gltf .glb .ply .stl
    material = "brick"             # a [materials] name, an inline table, or omitted (white, lit)
    transform = { translate = [0, 0, 0], rotate = { axis = [0, 1, 0], degrees = 30 }, scale = 1.0 }
    # or rotate = { euler = [x, y, z] } (degrees, X then Y then Z), or matrix = 4 rows of 4 (alone)

    [[lights]]                     # at most MAX_LIGHTS
    type = "directional"           # or "point" (with position instead of direction)
    direction = [-1, -1, -1]       # the way the light travels
    color = [1, 1, 1]
    intensity = 1.0

    [render]
    size = [800, 600]
    msaa = 4                       # 1 or 4
    hdr = true                     # render into rgba16float (needed by tone mapping)
    clear_color = [0, 0, 0, 1]     # linear
    output_format = "rgba8unorm-srgb"

    [[post]]                       # effects in order; the keys besides `effect` are its parameters
    effect = "tonemap"
    exposure = 1.0

Every mistake raises :class:`UserError` as ``FILE:LINE: what, and what is valid``.
tomllib gives no line numbers for values, so :class:`KeyLines` finds them by
scanning the text for table headers and keys.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import transforms
from .errors import UserError

MAX_LIGHTS = 8
CONVENTIONS = ("wgpu", "glm-vulkan")
LIGHT_TYPES = ("directional", "point")
MSAA_COUNTS = (1, 4)
OUTPUT_FORMATS = ("rgba8unorm-srgb", "rgba8unorm", "rgba16float")
FILTERS = ("linear", "nearest")
ADDRESS_MODES = ("repeat", "clamp-to-edge", "mirror-repeat")
MAX_ANISOTROPY = 16

TOP_KEYS = ("camera", "description", "lights", "materials", "models", "post", "render")
CAMERA_KEYS = ("convention", "eye", "far", "fov_y", "near", "target", "up")
MATERIAL_KEYS = (
    "albedo_color", "albedo_map", "normal_map", "roughness", "roughness_map", "sampler", "unlit", "uv_flip_v"
)
SAMPLER_KEYS = ("address_mode", "anisotropy", "filter", "mipmaps")
MODEL_KEYS = ("material", "path", "transform")
TRANSFORM_KEYS = ("matrix", "rotate", "scale", "translate")
LIGHT_KEYS = ("color", "direction", "intensity", "position", "type")
RENDER_KEYS = ("clear_color", "hdr", "msaa", "output_format", "size")

Vec3 = tuple[float, float, float]
Vec4 = tuple[float, float, float, float]
KeyPath = tuple  # of str (table keys) and int (array indices)


# ---------------------------------------------------------------------------
# Line numbers: where a key sits in the TOML text
# ---------------------------------------------------------------------------

_HEADER = re.compile(r"^\s*(\[\[?)\s*([^\[\]]+?)\s*\]\]?\s*$")
_KEY = re.compile(r"^\s*((?:[A-Za-z0-9_-]+|\"[^\"]*\"|'[^']*')(?:\s*\.\s*(?:[A-Za-z0-9_-]+|\"[^\"]*\"|'[^']*'))*)\s*=")
_INLINE_KEY = re.compile(r"([A-Za-z0-9_-]+|\"[^\"]*\")\s*=")


def _split_dotted(name: str) -> tuple[str, ...]:
    return tuple(part.strip().strip("\"'") for part in re.findall(r"\"[^\"]*\"|'[^']*'|[^.]+", name))


def _strip_comment(line: str) -> str:
    """The line without a trailing # comment (a # inside a string stays)."""
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            return line[:i]
    return line


def _bracket_depth(text: str) -> int:
    """Open [ and { minus closed ones, outside strings."""
    depth, quote = 0, None
    for ch in text:
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
    return depth


class KeyLines:
    """Maps key paths such as ``("models", 1, "transform", "rotate")`` to 1-based line numbers.

    Handles [table] and [[array]] headers (with dotted names), dotted keys, and keys
    inside one-line inline tables; values spanning lines (arrays) are skipped over.
    A path it cannot place falls back to its nearest known parent.
    """

    def __init__(self, text: str) -> None:
        self.lines: dict[KeyPath, int] = {}
        self._counts: dict[KeyPath, int] = {}
        table: KeyPath = ()
        depth = 0
        for number, raw in enumerate(text.splitlines(), start=1):
            line = _strip_comment(raw)
            if depth > 0:  # inside a value that spans lines
                depth += _bracket_depth(line)
                continue
            header = _HEADER.match(line)
            if header and not _KEY.match(line):
                table = self._header(header.group(1) == "[[", _split_dotted(header.group(2)), number)
                continue
            key = _KEY.match(line)
            if key:
                path = table + _split_dotted(key.group(1))
                self.lines.setdefault(path, number)
                rest = line[key.end() :]
                self._inline(path, rest, number)
                depth = _bracket_depth(rest)

    def _resolve(self, names: tuple[str, ...]) -> KeyPath:
        path: KeyPath = ()
        for name in names:
            path += (name,)
            if path in self._counts:
                path += (self._counts[path] - 1,)
        return path

    def _header(self, is_array: bool, names: tuple[str, ...], number: int) -> KeyPath:
        parent = self._resolve(names[:-1])
        path = parent + (names[-1],)
        if is_array:
            index = self._counts.get(path, 0)
            self._counts[path] = index + 1
            self.lines.setdefault(path, number)
            path += (index,)
        self.lines.setdefault(path, number)
        return path

    def _inline(self, path: KeyPath, rest: str, number: int) -> None:
        """Keys of inline tables on this line: ``material = { unlit = true, sampler = { filter = ... } }``."""
        stack: list[KeyPath] = []
        last_key: KeyPath | None = None
        i, quote = 0, None
        while i < len(rest):
            ch = rest[i]
            if quote:
                quote = None if ch == quote else quote
            elif ch in "\"'" and not _INLINE_KEY.match(rest, i):
                quote = ch
            elif ch == "{":
                stack.append(last_key if (stack and last_key) else path)
            elif ch == "}":
                if stack:
                    stack.pop()
            elif stack:
                m = _INLINE_KEY.match(rest, i)
                if m and (i == 0 or not (rest[i - 1].isalnum() or rest[i - 1] in "_-")):
                    last_key = stack[-1] + (m.group(1).strip("\""),)
                    self.lines.setdefault(last_key, number)
                    i = m.end()
                    continue
            i += 1

    def line_of(self, path: KeyPath) -> int | None:
        path = tuple(path)
        while path:
            if path in self.lines:
                return self.lines[path]
            path = path[:-1]
        return None


def format_path(path: KeyPath) -> str:
    """``("models", 0, "transform")`` -> ``models[0].transform``."""
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


# ---------------------------------------------------------------------------
# The scene dataclasses
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Camera:
    """A look-at camera with a perspective projection.

    ``convention = "glm-vulkan"``: the scene was set up for the Vulkan tutorial,
    whose projection is GLM's (right-handed, depth 0..1) with ``proj[1][1] *= -1``
    because Vulkan's NDC y points down. wgpu's NDC y points up (it flips to
    framebuffer rows itself), so drawn on wgpu that matrix gives an upside-down
    image, and the flip also turns every triangle's winding around, which is why
    the tutorial switches front_face to counter-clockwise. :meth:`source_projection`
    is the matrix as the convention writes it (what the raw-Vulkan reference path
    uploads); :meth:`projection` is what wgpu must use: ``clip_correction @
    source_projection``, which undoes the flip, so winding and orientation are the
    mesh's own again (counter-clockwise front faces).
    """

    eye: Vec3
    target: Vec3
    up: Vec3 = (0.0, 1.0, 0.0)
    fov_y: float = 45.0
    near: float = 0.1
    far: float = 100.0
    convention: str = "wgpu"

    def view(self) -> np.ndarray:
        return transforms.look_at(self.eye, self.target, self.up)

    def source_projection(self, aspect: float) -> np.ndarray:
        proj = transforms.perspective(self.fov_y, aspect, self.near, self.far)
        if self.convention == "glm-vulkan":
            proj[1, 1] *= -1.0
        return proj

    @property
    def clip_correction(self) -> np.ndarray:
        """diag(1, -1, 1, 1) for glm-vulkan (undoes the Y flip), identity otherwise."""
        return np.diag([1.0, -1.0 if self.convention == "glm-vulkan" else 1.0, 1.0, 1.0])

    def projection(self, aspect: float) -> np.ndarray:
        return self.clip_correction @ self.source_projection(aspect)


@dataclass(frozen=True)
class SamplerSettings:
    """How a material's textures are sampled. ``mipmaps`` also decides whether a mip chain is built.

    ``mipmaps = false`` with ``anisotropy > 1`` is the Vulkan tutorial's chapter-28 sampler: one mip level
    (maxLod 0) sampled anisotropically; the mipmap filter stays linear there because wgpu allows anisotropy
    only with linear min, mag and mipmap filters (with one level it changes nothing).
    """

    filter: str = "linear"
    mipmaps: bool = True
    anisotropy: int = 1
    address_mode: str = "repeat"

    def spec(self):
        """The :class:`wgpurender.textures.SamplerSpec` for these settings."""
        from .textures import SamplerSpec

        return SamplerSpec(
            mag_filter=self.filter,
            min_filter=self.filter,
            mipmap_filter=self.filter if (self.mipmaps or self.anisotropy > 1) else "nearest",
            address_mode_u=self.address_mode,
            address_mode_v=self.address_mode,
            address_mode_w=self.address_mode,
            max_anisotropy=self.anisotropy,
            lod_max_clamp=32.0 if self.mipmaps else 0.0,
        )


@dataclass(frozen=True)
class Material:
    """A surface. ``written`` keeps each key's value as the file wrote it (for the plan's explanations);
    ``origin`` says where it was defined, e.g. ``[materials.brick]`` or ``models[0].material (inline)``."""

    name: str
    albedo_color: Vec4 = (1.0, 1.0, 1.0, 1.0)
    albedo_map: Path | None = None
    normal_map: Path | None = None
    roughness_map: Path | None = None
    roughness: float = 0.5
    unlit: bool = False
    uv_flip_v: bool = False
    sampler: SamplerSettings = field(default_factory=SamplerSettings)
    origin: str = "default"
    written: tuple[tuple[str, str], ...] = ()

    @property
    def textures(self) -> dict[str, Path]:
        maps = {"albedo_map": self.albedo_map, "normal_map": self.normal_map, "roughness_map": self.roughness_map}
        return {k: v for k, v in maps.items() if v is not None}

    def as_written(self, key: str) -> str:
        return dict(self.written).get(key, "")


DEFAULT_MATERIAL = Material(name="default", origin="default (no material given)")


@dataclass(frozen=True)
class Transform:
    """The model's world matrix (row-major, acting on column vectors) and how it was written."""

    matrix: tuple[tuple[float, ...], ...]
    description: str = "identity"

    def array(self) -> np.ndarray:
        return np.array(self.matrix, dtype=np.float64)


def _rows(m: np.ndarray) -> tuple[tuple[float, ...], ...]:
    return tuple(tuple(float(v) for v in row) for row in m)


IDENTITY = Transform(_rows(np.eye(4)))


@dataclass(frozen=True)
class Model:
    index: int
    path: Path  # resolved
    written_path: str  # as in the file
    material: Material
    transform: Transform = IDENTITY

    @property
    def label(self) -> str:
        return f"models[{self.index}] '{self.written_path}'"


@dataclass(frozen=True)
class Light:
    """``direction`` (directional: the way the light travels) or ``position`` (point), linear colour."""

    index: int
    type: str
    color: Vec3 = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    direction: Vec3 | None = None
    position: Vec3 | None = None


@dataclass(frozen=True)
class RenderSettings:
    size: tuple[int, int] = (800, 600)
    msaa: int = 4
    hdr: bool = True
    clear_color: Vec4 = (0.0, 0.0, 0.0, 1.0)
    output_format: str = "rgba8unorm-srgb"


@dataclass(frozen=True)
class PostStep:
    """One [[post]] entry: an effect name and its validated parameters (defaults filled in)."""

    index: int
    effect: str
    params: tuple[tuple[str, float | str], ...] = ()
    written: tuple[str, ...] = ()  # the parameter names the file set

    def create(self):
        """The :class:`wgpurender.post.PostEffect` instance."""
        from .post import create_effect

        return create_effect(self.effect, **dict(self.params))


@dataclass(frozen=True)
class Scene:
    path: Path
    camera: Camera
    models: tuple[Model, ...] = ()
    materials: dict[str, Material] = field(default_factory=dict)
    lights: tuple[Light, ...] = ()
    render: RenderSettings = field(default_factory=RenderSettings)
    post: tuple[PostStep, ...] = ()
    description: str = ""

    @property
    def folder(self) -> Path:
        return self.path.parent


# ---------------------------------------------------------------------------
# Validation
# ---------------------------------------------------------------------------


def _type_name(value: Any) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "an array",
            dict: "a table"}.get(type(value), type(value).__name__)


class _Checker:
    """Type and value checks that fail with FILE:LINE messages."""

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.folder = path.parent
        self.keys = KeyLines(text)

    def error(self, key: KeyPath, message: str) -> UserError:
        line = self.keys.line_of(key)
        where = f"{self.path}:{line}" if line else f"{self.path}"
        return UserError(f"{where}: {message}")

    def table(self, value: Any, key: KeyPath, allowed: tuple[str, ...], required: tuple[str, ...] = ()) -> dict:
        name = format_path(key) or "the top level"
        if not isinstance(value, dict):
            raise self.error(key, f"{name} must be a table, got {_type_name(value)}")
        for k in value:
            if k not in allowed:
                raise self.error(key + (k,), f"unknown key '{k}' in {name}: valid keys are {', '.join(allowed)}")
        for k in required:
            if k not in value:
                raise self.error(key, f"{name} needs '{k}'")
        return value

    def number(self, value: Any, key: KeyPath, lo: float = -math.inf, hi: float = math.inf,
               open_lo: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(key, f"{format_path(key)} must be a number, got {_type_name(value)} {value!r}")
        if value < lo or value > hi or (open_lo and value == lo):
            low = f"> {lo}" if open_lo else f">= {lo}"
            bounds = low if hi == math.inf else f"in [{lo}, {hi}]"
            raise self.error(key, f"{format_path(key)} must be {bounds}, got {value}")
        return float(value)

    def integer(self, value: Any, key: KeyPath, choices: tuple[int, ...] | None = None,
                lo: int | None = None, hi: int | None = None) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(key, f"{format_path(key)} must be an integer, got {_type_name(value)} {value!r}")
        if choices is not None and value not in choices:
            raise self.error(key, f"{format_path(key)} must be one of {', '.join(map(str, choices))}, got {value}")
        if (lo is not None and value < lo) or (hi is not None and value > hi):
            raise self.error(key, f"{format_path(key)} must be in {lo}..{hi}, got {value}")
        return value

    def boolean(self, value: Any, key: KeyPath) -> bool:
        if not isinstance(value, bool):
            raise self.error(key, f"{format_path(key)} must be true or false, got {_type_name(value)} {value!r}")
        return value

    def string(self, value: Any, key: KeyPath, choices: tuple[str, ...] | None = None) -> str:
        if not isinstance(value, str):
            raise self.error(key, f"{format_path(key)} must be a string, got {_type_name(value)} {value!r}")
        if choices is not None and value not in choices:
            raise self.error(key, f"{format_path(key)} must be one of {', '.join(choices)}, got {value!r}")
        return value

    def vector(self, value: Any, key: KeyPath, lengths: tuple[int, ...] = (3,), nonzero: bool = False) -> tuple:
        want = " or ".join(map(str, lengths))
        if not isinstance(value, list) or len(value) not in lengths:
            raise self.error(key, f"{format_path(key)} must be an array of {want} numbers, got {value!r}")
        out = tuple(self.number(v, key) for v in value)
        if nonzero and not any(out):
            raise self.error(key, f"{format_path(key)} must not be all zeros")
        return out

    def file(self, value: Any, key: KeyPath, what: str) -> Path:
        written = self.string(value, key)
        path = (self.folder / written).resolve()
        if not path.is_file():
            raise self.error(
                key,
                f"{format_path(key)}: {what} '{written}' not found (looked for {path}; "
                f"paths are relative to the scene file's folder {self.folder})",
            )
        return path


def _camera(c: _Checker, data: Any) -> Camera:
    key = ("camera",)
    t = c.table(data, key, CAMERA_KEYS, required=("eye", "target"))
    cam = Camera(
        eye=c.vector(t["eye"], key + ("eye",)),
        target=c.vector(t["target"], key + ("target",)),
        up=c.vector(t.get("up", [0, 1, 0]), key + ("up",), nonzero=True),
        fov_y=c.number(t.get("fov_y", 45.0), key + ("fov_y",), 0.0, 180.0, open_lo=True),
        near=c.number(t.get("near", 0.1), key + ("near",), 0.0, open_lo=True),
        far=c.number(t.get("far", 100.0), key + ("far",), 0.0, open_lo=True),
        convention=c.string(t.get("convention", "wgpu"), key + ("convention",), CONVENTIONS),
    )
    if cam.fov_y >= 180:
        raise c.error(key + ("fov_y",), f"camera.fov_y must be below 180 degrees, got {cam.fov_y}")
    if cam.far <= cam.near:
        raise c.error(key + ("far",), f"camera.far ({cam.far}) must be greater than camera.near ({cam.near})")
    if cam.eye == cam.target:
        raise c.error(key + ("target",), "camera.eye and camera.target are the same point")
    try:
        cam.view()
    except ValueError as err:
        raise c.error(key + ("up",), f"camera: {err}") from None
    return cam


def _sampler(c: _Checker, data: Any, key: KeyPath) -> SamplerSettings:
    t = c.table(data, key, SAMPLER_KEYS)
    s = SamplerSettings(
        filter=c.string(t.get("filter", "linear"), key + ("filter",), FILTERS),
        mipmaps=c.boolean(t.get("mipmaps", True), key + ("mipmaps",)),
        anisotropy=c.integer(t.get("anisotropy", 1), key + ("anisotropy",), lo=1, hi=MAX_ANISOTROPY),
        address_mode=c.string(t.get("address_mode", "repeat"), key + ("address_mode",), ADDRESS_MODES),
    )
    if s.anisotropy > 1 and s.filter != "linear":
        raise c.error(
            key + ("anisotropy",),
            f"{format_path(key)}: anisotropy {s.anisotropy} needs filter = \"linear\" "
            "(wgpu allows anisotropic filtering only with linear min, mag and mipmap filters)",
        )
    return s


def _material(c: _Checker, data: Any, key: KeyPath, name: str, origin: str) -> Material:
    t = c.table(data, key, MATERIAL_KEYS)
    written = tuple((k, v if isinstance(v, str) else repr(v)) for k, v in t.items() if k != "sampler")
    maps = {k: c.file(t[k], key + (k,), "texture") for k in ("albedo_map", "normal_map", "roughness_map") if k in t}
    return Material(
        name=name,
        albedo_color=_color(c, t.get("albedo_color", [1, 1, 1, 1]), key + ("albedo_color",)),
        roughness=c.number(t.get("roughness", 0.5), key + ("roughness",), 0.0, 1.0),
        unlit=c.boolean(t.get("unlit", False), key + ("unlit",)),
        uv_flip_v=c.boolean(t.get("uv_flip_v", False), key + ("uv_flip_v",)),
        sampler=_sampler(c, t.get("sampler", {}), key + ("sampler",)),
        origin=origin,
        written=written,
        **maps,
    )


def _color(c: _Checker, value: Any, key: KeyPath) -> Vec4:
    v = c.vector(value, key, lengths=(3, 4))
    if min(v) < 0:
        raise c.error(key, f"{format_path(key)} must not be negative, got {list(v)}")
    return v if len(v) == 4 else (*v, 1.0)


def _transform(c: _Checker, data: Any, key: KeyPath) -> Transform:
    t = c.table(data, key, TRANSFORM_KEYS)
    if "matrix" in t:
        others = sorted(set(t) - {"matrix"})
        if others:
            raise c.error(key + (others[0],), f"{format_path(key)}: matrix cannot be combined with {', '.join(others)}")
        rows = t["matrix"]
        if not isinstance(rows, list) or len(rows) != 4:
            raise c.error(key + ("matrix",), f"{format_path(key)}.matrix must be 4 rows of 4 numbers")
        m = np.array([c.vector(r, key + ("matrix",), lengths=(4,)) for r in rows])
        if abs(np.linalg.det(m[:3, :3])) < 1e-12:
            raise c.error(key + ("matrix",), f"{format_path(key)}.matrix is singular (its 3x3 part has determinant 0)")
        return Transform(_rows(m), "matrix")
    parts, m = [], np.eye(4)
    if "translate" in t:
        offset = c.vector(t["translate"], key + ("translate",))
        m = m @ transforms.translate(offset)
        parts.append(f"translate {list(offset)}")
    if "rotate" in t:
        rot, text = _rotation(c, t["rotate"], key + ("rotate",))
        m = m @ rot
        parts.append(text)
    if "scale" in t:
        s = t["scale"]
        factors = (c.number(s, key + ("scale",)),) * 3 if not isinstance(s, list) else c.vector(s, key + ("scale",))
        if not all(factors):
            raise c.error(key + ("scale",), f"{format_path(key)}.scale must not be 0 on any axis")
        m = m @ transforms.scale(factors)
        parts.append(f"scale {list(factors) if isinstance(s, list) else factors[0]}")
    return Transform(_rows(m), ", ".join(parts) or "identity")


def _rotation(c: _Checker, data: Any, key: KeyPath) -> tuple[np.ndarray, str]:
    """{axis, degrees} (right-hand rule) or {euler = [x, y, z]} in degrees, applied X first: Rz @ Ry @ Rx."""
    t = c.table(data, key, ("axis", "degrees", "euler"))
    if "euler" in t:
        if set(t) != {"euler"}:
            raise c.error(key, f"{format_path(key)}: give either euler, or axis and degrees")
        ex, ey, ez = c.vector(t["euler"], key + ("euler",))
        rot = (transforms.rotate((0, 0, 1), math.radians(ez)) @ transforms.rotate((0, 1, 0), math.radians(ey))
               @ transforms.rotate((1, 0, 0), math.radians(ex)))
        return rot, f"rotate euler XYZ [{ex}, {ey}, {ez}] deg"
    if set(t) != {"axis", "degrees"}:
        raise c.error(key, f"{format_path(key)}: give either euler, or axis and degrees")
    axis = c.vector(t["axis"], key + ("axis",), nonzero=True)
    degrees = c.number(t["degrees"], key + ("degrees",))
    return transforms.rotate(axis, math.radians(degrees)), f"rotate {degrees} deg about {list(axis)}"


def _model_path(c: _Checker, value: Any, key: KeyPath) -> Path:
    from .mesh import SUPPORTED, UNSUPPORTED

    written = c.string(value, key)
    suffix = Path(written).suffix.lower()
    if suffix in UNSUPPORTED:
        raise c.error(key, f"{format_path(key)}: '{written}' is {UNSUPPORTED[suffix]}, which cannot be loaded: "
                           f"convert it to glTF (.glb); supported formats: {', '.join(SUPPORTED)}")
    if suffix not in SUPPORTED:
        raise c.error(key, f"{format_path(key)}: '{written}' has an unknown model format "
                           f"(supported: {', '.join(SUPPORTED)})")
    return c.file(written, key, "model file")


def _models(c: _Checker, data: Any, materials: dict[str, Material]) -> tuple[Model, ...]:
    if not isinstance(data, list):
        raise c.error(("models",), "models must be an array of tables: write each as [[models]]")
    out = []
    for i, entry in enumerate(data):
        key = ("models", i)
        t = c.table(entry, key, MODEL_KEYS, required=("path",))
        material = DEFAULT_MATERIAL
        if "material" in t:
            m = t["material"]
            if isinstance(m, str):
                if m not in materials:
                    valid = ", ".join(sorted(materials)) or "none defined"
                    raise c.error(key + ("material",), f"models[{i}].material: no material '{m}' "
                                                       f"(materials: {valid}; define it as [materials.{m}])")
                material = materials[m]
            else:
                material = _material(c, m, key + ("material",), f"models[{i}]", f"models[{i}].material (inline)")
        out.append(
            Model(
                index=i,
                path=_model_path(c, t["path"], key + ("path",)),
                written_path=t["path"],
                material=material,
                transform=_transform(c, t.get("transform", {}), key + ("transform",)),
            )
        )
    return tuple(out)


def _lights(c: _Checker, data: Any) -> tuple[Light, ...]:
    if not isinstance(data, list):
        raise c.error(("lights",), "lights must be an array of tables: write each as [[lights]]")
    if len(data) > MAX_LIGHTS:
        raise c.error(("lights", MAX_LIGHTS), f"{len(data)} lights, but at most MAX_LIGHTS = {MAX_LIGHTS} are "
                                              f"supported: remove {len(data) - MAX_LIGHTS}")
    out = []
    for i, entry in enumerate(data):
        key = ("lights", i)
        t = c.table(entry, key, LIGHT_KEYS, required=("type",))
        kind = c.string(t["type"], key + ("type",), LIGHT_TYPES)
        needs, forbids = ("direction", "position") if kind == "directional" else ("position", "direction")
        if needs not in t:
            raise c.error(key, f"lights[{i}]: a {kind} light needs '{needs}'")
        if forbids in t:
            raise c.error(key + (forbids,), f"lights[{i}]: a {kind} light has no '{forbids}' (it has '{needs}')")
        color = _color(c, t.get("color", [1, 1, 1]), key + ("color",))
        out.append(
            Light(
                index=i,
                type=kind,
                color=color[:3],
                intensity=c.number(t.get("intensity", 1.0), key + ("intensity",), 0.0),
                direction=c.vector(t[needs], key + (needs,), nonzero=True) if kind == "directional" else None,
                position=c.vector(t[needs], key + (needs,)) if kind == "point" else None,
            )
        )
    return tuple(out)


def _render(c: _Checker, data: Any) -> RenderSettings:
    key = ("render",)
    t = c.table(data, key, RENDER_KEYS)
    size = t.get("size", [800, 600])
    if not isinstance(size, list) or len(size) != 2:
        raise c.error(key + ("size",), f"render.size must be [width, height], got {size!r}")
    w, h = (c.integer(v, key + ("size",), lo=1, hi=16384) for v in size)
    return RenderSettings(
        size=(w, h),
        msaa=c.integer(t.get("msaa", 4), key + ("msaa",), choices=MSAA_COUNTS),
        hdr=c.boolean(t.get("hdr", True), key + ("hdr",)),
        clear_color=_color(c, t.get("clear_color", [0, 0, 0, 1]), key + ("clear_color",)),
        output_format=c.string(t.get("output_format", "rgba8unorm-srgb"), key + ("output_format",), OUTPUT_FORMATS),
    )


def _post(c: _Checker, data: Any) -> tuple[PostStep, ...]:
    from .post import EFFECTS, check_order, effect_names

    if not isinstance(data, list):
        raise c.error(("post",), "post must be an array of tables: write each effect as [[post]]")
    steps = []
    for i, entry in enumerate(data):
        key = ("post", i)
        if not isinstance(entry, dict):
            raise c.error(key, f"post[{i}] must be a table, got {_type_name(entry)}")
        if "effect" not in entry:
            raise c.error(key, f"post[{i}] needs 'effect': one of {', '.join(effect_names())}")
        name = c.string(entry["effect"], key + ("effect",))
        if name not in EFFECTS:
            raise c.error(key + ("effect",), f"post[{i}]: unknown effect '{name}': valid effects are "
                                             f"{', '.join(effect_names())}")
        cls = EFFECTS[name]
        specs = {p.name: p for p in cls.params_spec}
        params = {k: v for k, v in entry.items() if k != "effect"}
        c.table(params, key, ("effect", *specs))
        try:
            effect = cls(**params)
        except UserError as err:
            bad = next((k for k in params if k in specs), None)
            raise c.error(key + ((bad,) if bad else ()), f"post[{i}]: {err}") from None
        steps.append(PostStep(index=i, effect=name, params=tuple(effect.params.items()), written=tuple(params)))
    try:
        check_order([s.create() for s in steps])
    except UserError as err:
        raise c.error(("post", len(steps) - 1), str(err)) from None
    return tuple(steps)


def parse_scene(text: str, path: str | Path = "<scene>") -> Scene:
    """Validate TOML text as a scene whose file is ``path`` (relative paths resolve from its folder)."""
    path = Path(path).absolute()
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise UserError(f"{path}: invalid TOML: {err}") from None
    c = _Checker(path, text)
    c.table(data, (), TOP_KEYS, required=("camera",))
    materials = {}
    mats = data.get("materials", {})
    c.table(mats, ("materials",), tuple(mats) if isinstance(mats, dict) else ())
    for name, body in mats.items():
        materials[name] = _material(c, body, ("materials", name), name, f"[materials.{name}]")
    description = data.get("description", "")
    return Scene(
        path=path,
        camera=_camera(c, data["camera"]),
        models=_models(c, data.get("models", []), materials),
        materials=materials,
        lights=_lights(c, data.get("lights", [])),
        render=_render(c, data.get("render", {})),
        post=_post(c, data.get("post", [])),
        description=c.string(description, ("description",)),
    )


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file."""
    path = Path(path)
    if not path.is_file():
        raise UserError(f"scene file not found: {path}")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        raise UserError(f"cannot read scene file {path}: {err}") from None
    return parse_scene(text, path)
