"""Uniform-buffer layouts declared once in Python: offsets, a packer, and the WGSL struct text.

The course's alignment chapter shows what goes wrong when the C++ struct and the
shader block disagree (a ``vec2`` before a ``mat4``, a nested struct holding one
``vec2``) and patches it with ``alignas(16)``. Here both sides come from one
definition, so they cannot disagree::

    CAMERA = Struct("Camera", [("proj", MAT4), ("view", MAT4), ("light_dir", VEC3F), ("ambient", F32)])
    CAMERA.offsets            # {'proj': 0, 'view': 64, 'light_dir': 128, 'ambient': 140}
    CAMERA.size               # 144
    CAMERA.pack({...})        # bytes for queue.write_buffer
    CAMERA.wgsl()             # "struct Camera { ... }" for the shader

Layout rules: WGSL's uniform address space, which for the types below equals GLSL
std140 (the layout Vulkan's uniform blocks use):

- f32/i32/u32: align 4, size 4; vec2: align 8, size 8; vec3: align 16, size 12
  (a following scalar goes into its padding, at +12); vec4: align 16, size 16;
- mat3x3f: three vec3 columns, each padded to 16 bytes: align 16, size 48;
  mat4x4f: align 16, size 64;
- struct: alignment rounded up to 16, size rounded up to that alignment, so the
  member after a nested struct starts at a multiple of 16;
- array<E, N>: alignment rounded up to 16, element stride rounded up to 16
  (an f32 array takes 16 bytes per element).

WGSL has no per-array stride attribute, so an array whose element would have a
stride below 16 (f32/i32/u32 and vec2 elements) is declared as ``array<vec4f, N>``
(vec4i/vec4u for integers): element i of ``a: array<f32, N>`` is read ``u.a[i].x``
in the shader, and a vec2 element ``u.a[i].xy``. Every other field is declared with
the type it was given. Members get ``@size(n)`` where the padding WGSL would not
insert by itself is needed; the layout is then the same in any address space.

Matrices are given in the usual math orientation (numpy ``m[row, col]``, acting on
column vectors) and packed column-major through :func:`wgpurender.core.view.transforms.to_gpu`,
the one place a transpose happens: the shader's ``m[c][r]`` is ``m[r, c]`` here.

Not expressible (raises :class:`UserError` when the definition is made): bool (not
host-shareable), f16 (needs the shader-f16 feature), matrices other than mat3x3f and
mat4x4f (std140 and WGSL disagree on mat2 layouts), runtime-sized or empty arrays,
empty structs, duplicate fields, and names that are not plain ASCII WGSL identifiers.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.view.transforms import to_gpu

UNIFORM_ALIGN = 16  # structs and arrays in uniform space: alignment and stride rounded up to this


def round_up(value: int, multiple: int) -> int:
    return (value + multiple - 1) // multiple * multiple


# --------------------------------------------------------------------------- types


class UniformType:
    """A type that can live in a uniform buffer: its alignment, size and WGSL spelling."""

    align: int
    size: int

    @property
    def wgsl_name(self) -> str:
        raise NotImplementedError

    def leaves(self, path: tuple, expr: str, offset: int) -> Iterator[Leaf]:
        raise NotImplementedError

    def pack_into(self, buf: bytearray, offset: int, value, where: str) -> None:
        raise NotImplementedError


@dataclass(frozen=True)
class Leaf:
    """One scalar of a struct: where it is in Python values, in WGSL, and in the bytes.

    ``path`` indexes the value given to :meth:`Struct.pack` (field names and integer
    indices; a matrix element is ``(..., row, col)``), ``expr`` reads the same scalar
    in WGSL from a variable named by the caller, ``offset`` is its byte offset.
    """

    path: tuple
    expr: str
    scalar: Scalar
    offset: int


@dataclass(frozen=True)
class Scalar(UniformType):
    name: str  # WGSL name
    dtype: str  # numpy dtype, little-endian
    suffix: str  # vecN<suffix> shorthand letter

    align = 4
    size = 4

    @property
    def wgsl_name(self) -> str:
        return self.name

    def leaves(self, path, expr, offset):
        yield Leaf(path, expr, self, offset)

    def convert(self, value, where: str) -> np.ndarray:
        """The value as a 0-d array of this scalar's dtype, or UserError if it does not fit."""
        if self.name == "f32":
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
                raise UserError(f"{where}: f32 needs a number, got {value!r}")
            out = np.asarray(value, dtype=np.float64)
            if math.isfinite(float(out)) and abs(float(out)) > float(np.finfo(np.float32).max):
                raise UserError(f"{where}: {value!r} is outside the f32 range (max {np.finfo(np.float32).max:g})")
            return out.astype(np.float32)
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
            raise UserError(f"{where}: {self.name} needs an integer, got {value!r} (convert it explicitly)")
        info = np.iinfo(self.dtype)
        if not info.min <= int(value) <= info.max:
            raise UserError(f"{where}: {value} is outside the {self.name} range {info.min}..{info.max}")
        return np.asarray(int(value), dtype=self.dtype)

    def pack_into(self, buf, offset, value, where):
        buf[offset : offset + 4] = self.convert(value, where).astype(self.dtype).tobytes()


F32 = Scalar("f32", "<f4", "f")
I32 = Scalar("i32", "<i4", "i")
U32 = Scalar("u32", "<u4", "u")
_COMPONENTS = "xyzw"


@dataclass(frozen=True)
class Vector(UniformType):
    scalar: Scalar
    n: int

    @property
    def align(self) -> int:
        return 8 if self.n == 2 else 16

    @property
    def size(self) -> int:
        return 4 * self.n

    @property
    def wgsl_name(self) -> str:
        return f"vec{self.n}{self.scalar.suffix}"

    def leaves(self, path, expr, offset):
        for i in range(self.n):
            yield Leaf(path + (i,), f"{expr}.{_COMPONENTS[i]}", self.scalar, offset + 4 * i)

    def pack_into(self, buf, offset, value, where):
        items = _sequence(value, self.n, where, self.wgsl_name)
        for i, item in enumerate(items):
            self.scalar.pack_into(buf, offset + 4 * i, item, f"{where}[{i}]")


@dataclass(frozen=True)
class Matrix(UniformType):
    """A square f32 matrix, stored as ``n`` columns of vec``n`` each padded to 16 bytes."""

    n: int

    align = 16

    @property
    def size(self) -> int:
        return 16 * self.n

    @property
    def wgsl_name(self) -> str:
        return f"mat{self.n}x{self.n}f"

    def leaves(self, path, expr, offset):
        for c in range(self.n):
            for r in range(self.n):
                yield Leaf(path + (r, c), f"{expr}[{c}].{_COMPONENTS[r]}", F32, offset + 16 * c + 4 * r)

    def pack_into(self, buf, offset, value, where):
        try:
            m = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError):
            raise UserError(f"{where}: {self.wgsl_name} needs a {self.n}x{self.n} array of numbers") from None
        if m.shape != (self.n, self.n):
            raise UserError(f"{where}: {self.wgsl_name} needs a {self.n}x{self.n} matrix, got shape {m.shape}")
        if np.isfinite(m).all() and np.abs(m).max() > np.finfo(np.float32).max:
            raise UserError(f"{where}: a matrix element is outside the f32 range")
        columns = to_gpu(m)  # row c is column c of the math matrix
        for c in range(self.n):
            buf[offset + 16 * c : offset + 16 * c + 4 * self.n] = columns[c].astype("<f4").tobytes()


MAT3 = MAT3X3F = Matrix(3)
MAT4 = MAT4X4F = Matrix(4)


@dataclass(frozen=True)
class Array(UniformType):
    """``array<element, count>`` with the uniform-space stride (a multiple of 16)."""

    element: UniformType
    count: int

    def __post_init__(self) -> None:
        elem = _resolve(self.element, "array element")
        object.__setattr__(self, "element", elem)
        if isinstance(self.count, bool) or not isinstance(self.count, (int, np.integer)) or self.count < 1:
            raise UserError(
                f"array<{elem.wgsl_name}, {self.count!r}>: the length must be an integer >= 1 "
                "(uniform buffers cannot hold runtime-sized or empty arrays)"
            )
        object.__setattr__(self, "count", int(self.count))

    @property
    def align(self) -> int:
        return round_up(self.element.align, UNIFORM_ALIGN)

    @property
    def stride(self) -> int:
        return round_up(round_up(self.element.size, self.element.align), UNIFORM_ALIGN)

    @property
    def size(self) -> int:
        return self.stride * self.count

    @property
    def padded_element(self) -> bool:
        """True when WGSL must see the element as a vec4 (its natural stride is below 16)."""
        return isinstance(self.element, Scalar) or (isinstance(self.element, Vector) and self.element.n == 2)

    @property
    def wgsl_name(self) -> str:
        if self.padded_element:
            scalar = self.element if isinstance(self.element, Scalar) else self.element.scalar
            return f"array<vec4{scalar.suffix}, {self.count}>"
        return f"array<{self.element.wgsl_name}, {self.count}>"

    def leaves(self, path, expr, offset):
        for i in range(self.count):
            # A padded scalar element is the .x of a vec4; a padded vec2's components are .x, .y.
            elem_expr = f"{expr}[{i}].x" if isinstance(self.element, Scalar) else f"{expr}[{i}]"
            yield from self.element.leaves(path + (i,), elem_expr, offset + i * self.stride)

    def pack_into(self, buf, offset, value, where):
        items = _sequence(value, self.count, where, type_name(self))
        for i, item in enumerate(items):
            self.element.pack_into(buf, offset + i * self.stride, item, f"{where}[{i}]")


@dataclass(frozen=True)
class Field:
    """One member of a struct, with its place in the struct (offset relative to the struct start)."""

    name: str
    type: UniformType
    offset: int
    size: int
    align: int


class Struct(UniformType):
    """A uniform struct: a name and ordered (field name, type) pairs; the layout is computed at once.

    Field types are the constants of this module (F32, VEC3F, MAT4, ...), their WGSL
    names as strings ("vec3f", "mat4x4<f32>"), ``Array(type, n)`` or another Struct.
    """

    def __init__(self, name: str, fields: Sequence[tuple[str, UniformType | str]]) -> None:
        self.name = check_identifier(name, "struct name")
        if isinstance(fields, (str, bytes, Mapping)) or not isinstance(fields, Sequence) or not fields:
            raise UserError(f"struct {name}: give the fields as a non-empty list of (name, type) pairs")
        laid_out: list[Field] = []
        cursor = 0
        for item in fields:
            if not (isinstance(item, (tuple, list)) and len(item) == 2):
                raise UserError(f"struct {name}: each field must be a (name, type) pair, got {item!r}")
            fname = check_identifier(item[0], f"field name in struct {name}")
            if any(f.name == fname for f in laid_out):
                raise UserError(f"struct {name}: field {fname!r} is declared twice")
            ftype = _resolve(item[1], f"{name}.{fname}")
            offset = round_up(cursor, ftype.align)
            laid_out.append(Field(fname, ftype, offset, ftype.size, ftype.align))
            cursor = offset + ftype.size
        self.fields: tuple[Field, ...] = tuple(laid_out)
        self.align = round_up(max(f.align for f in laid_out), UNIFORM_ALIGN)
        self.size = round_up(cursor, self.align)

    # -- layout ---------------------------------------------------------------
    @property
    def wgsl_name(self) -> str:
        return self.name

    @property
    def offsets(self) -> dict[str, int]:
        """Byte offset of each top-level field."""
        return {f.name: f.offset for f in self.fields}

    def field(self, name: str) -> Field:
        for f in self.fields:
            if f.name == name:
                return f
        raise UserError(f"struct {self.name} has no field {name!r}: fields are {', '.join(self.offsets)}")

    def flat_offsets(self) -> dict[str, int]:
        """Absolute offset of every field, nested ones too: {"f2": 16, "f2.v": 16, "a[1]": 16, ...}."""
        out: dict[str, int] = {}

        def walk(prefix: str, t: UniformType, base: int) -> None:
            if isinstance(t, Struct):
                for f in t.fields:
                    name = f"{prefix}.{f.name}" if prefix else f.name
                    out[name] = base + f.offset
                    walk(name, f.type, base + f.offset)
            elif isinstance(t, Array):
                for i in range(t.count):
                    out[f"{prefix}[{i}]"] = base + i * t.stride
                    walk(f"{prefix}[{i}]", t.element, base + i * t.stride)

        walk("", self, 0)
        return out

    def stride(self, alignment: int) -> int:
        """Distance between consecutive copies in one buffer read with dynamic offsets of ``alignment``."""
        return round_up(self.size, alignment)

    def leaves(self, path: tuple = (), expr: str = "u", offset: int = 0) -> Iterator[Leaf]:
        """Every scalar in declaration order, for generated shaders that read the struct (see Leaf)."""
        for f in self.fields:
            yield from f.type.leaves(path + (f.name,), f"{expr}.{f.name}", offset + f.offset)

    def nested_structs(self) -> list[Struct]:
        """Structs this one uses, dependencies first, without itself."""
        found: list[Struct] = []

        def visit(t: UniformType) -> None:
            while isinstance(t, Array):
                t = t.element
            if isinstance(t, Struct):
                for f in t.fields:
                    visit(f.type)
                if t is not self and t not in found:
                    found.append(t)

        visit(self)
        return found

    # -- packing --------------------------------------------------------------
    def pack(self, values: Mapping) -> bytes:
        """The struct's bytes (``size`` long, padding zeroed) from a dict of field values."""
        buf = bytearray(self.size)
        self.pack_into(buf, 0, values, self.name)
        return bytes(buf)

    def pack_many(self, items: Sequence[Mapping], alignment: int) -> bytes:
        """Several copies at ``stride(alignment)`` apart: one buffer for dynamic offsets."""
        stride = self.stride(alignment)
        buf = bytearray(stride * len(items))
        for i, values in enumerate(items):
            self.pack_into(buf, i * stride, values, f"{self.name}[{i}]")
        return bytes(buf)

    def pack_into(self, buf, offset, value, where):
        if not isinstance(value, Mapping):
            raise UserError(f"{where}: struct {self.name} needs a dict of its fields, got {type(value).__name__}")
        names = [f.name for f in self.fields]
        missing = [n for n in names if n not in value]
        extra = [str(k) for k in value if k not in names]
        if missing or extra:
            parts = ([f"missing {', '.join(missing)}"] if missing else []) + (
                [f"unknown {', '.join(extra)}"] if extra else []
            )
            raise UserError(f"{where}: {'; '.join(parts)} (struct {self.name} has fields {', '.join(names)})")
        for f in self.fields:
            f.type.pack_into(buf, offset + f.offset, value[f.name], f"{where}.{f.name}")

    # -- WGSL -----------------------------------------------------------------
    def wgsl(self) -> str:
        """This struct's WGSL declaration alone (see :func:`wgsl_structs` for nested ones)."""
        lines = [f"struct {self.name} {{"]
        for i, f in enumerate(self.fields):
            end = self.fields[i + 1].offset if i + 1 < len(self.fields) else self.size
            natural_align, natural_size = _natural(f.type)
            assert f.offset % natural_align == 0  # our alignment is a multiple of WGSL's
            attr = f"@size({end - f.offset}) " if end - f.offset != natural_size else ""
            lines.append(f"    {attr}{f.name}: {f.type.wgsl_name},")
        lines.append("}")
        return "\n".join(lines) + "\n"

    def __eq__(self, other) -> bool:
        return isinstance(other, Struct) and (self.name, self.fields) == (other.name, other.fields)

    def __hash__(self) -> int:
        return hash((self.name, self.fields))

    def __repr__(self) -> str:
        inner = ", ".join(f"{f.name}: {type_name(f.type)} @{f.offset}" for f in self.fields)
        return f"Struct({self.name}: {inner}; size {self.size})"


def type_name(t: UniformType) -> str:
    """The type as it was defined ("array<f32, 4>"), not as it is declared in WGSL ("array<vec4f, 4>")."""
    if isinstance(t, Array):
        return f"array<{type_name(t.element)}, {t.count}>"
    return t.wgsl_name


def wgsl_structs(*structs: Struct) -> str:
    """WGSL declarations of several structs and everything they nest, each once, dependencies first."""
    ordered: list[Struct] = []
    for s in structs:
        if not isinstance(s, Struct):
            raise UserError(f"wgsl_structs takes Struct definitions, got {s!r}")
        for dep in [*s.nested_structs(), s]:
            clash = next((o for o in ordered if o.name == dep.name), None)
            if clash is not None and clash != dep:
                raise UserError(f"two different structs are both named {dep.name!r}: rename one")
            if clash is None:
                ordered.append(dep)
    return "\n".join(s.wgsl() for s in ordered)


def _natural(t: UniformType) -> tuple[int, int]:
    """WGSL's own (align, size) of the type as we declare it, before any @size of ours.

    Equal to ours except that WGSL does not round struct/array alignment up to 16;
    padded arrays are declared as vec4 arrays, so their size already matches.
    """
    if isinstance(t, Struct):
        return max(_natural(f.type)[0] for f in t.fields), t.size  # the last @size makes it t.size
    if isinstance(t, Array):
        if t.padded_element:
            return 16, 16 * t.count
        return _natural(t.element)[0], t.size
    return t.align, t.size


# --------------------------------------------------------------------------- names and parsing

VEC2F, VEC3F, VEC4F = (Vector(F32, n) for n in (2, 3, 4))
VEC2I, VEC3I, VEC4I = (Vector(I32, n) for n in (2, 3, 4))
VEC2U, VEC3U, VEC4U = (Vector(U32, n) for n in (2, 3, 4))

_BY_NAME: dict[str, UniformType] = {"f32": F32, "i32": I32, "u32": U32, "mat3x3f": MAT3, "mat4x4f": MAT4}
_BY_NAME.update({v.wgsl_name: v for v in (VEC2F, VEC3F, VEC4F, VEC2I, VEC3I, VEC4I, VEC2U, VEC3U, VEC4U)})
_BY_NAME.update({f"vec{v.n}<{v.scalar.name}>": v for v in list(_BY_NAME.values()) if isinstance(v, Vector)})
_BY_NAME.update({"mat3x3<f32>": MAT3, "mat4x4<f32>": MAT4})

_REFUSED = [
    (re.compile(r"^bool$|^vec[234]<bool>$"), "bool is not host-shareable: WGSL forbids it in buffers; use u32 0/1"),
    (re.compile(r"f16|^vec[234]h$"), "f16 needs the shader-f16 feature, which wgpurender does not enable; use f32"),
    (
        re.compile(r"^mat[234]x[234]"),
        "only mat3x3f and mat4x4f are supported (std140 and WGSL lay out the other matrices differently)",
    ),
    (re.compile(r"^array"), "write arrays as Array(element_type, length), not as a string"),
    (re.compile(r"^(atomic|ptr|sampler|texture)"), "only plain data can live in a uniform struct"),
]

_ID = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
# WGSL keywords and reserved words (WGSL spec 3.6-3.7), plus the type names of this module.
_RESERVED = set(
    """alias break case const const_assert continue continuing default diagnostic discard else enable false fn for
    if let loop override requires return struct switch true var while
    NULL Self abstract active alignas alignof as asm asm_fragment async attribute auto await become cast catch class
    co_await co_return co_yield coherent column_major common compile compile_fragment concept const_cast consteval
    constexpr constinit crate debugger decltype delete demote demote_to_helper do dynamic_cast enum explicit export
    extends extern external fallthrough filter final finally friend from fxgroup get goto groupshared highp impl
    implements import inline instanceof interface layout lowp macro macro_rules match mediump meta mod module move mut
    mutable namespace new nil noexcept noinline nointerpolation non_coherent noncoherent noperspective null nullptr of
    operator package packoffset partition pass patch pixelfragment precise precision premerge priv protected pub
    public readonly ref regardless register reinterpret_cast require resource restrict self set shared sizeof smooth
    snorm static static_assert static_cast std subroutine super target template this thread_local throw trait try
    type typedef typeid typename typeof union unless unorm unsafe unsized use using varying virtual volatile wgsl
    where with writeonly yield
    bool f16 f32 i32 u32 array atomic ptr sampler sampler_comparison vec2 vec3 vec4 mat2x2 mat2x3 mat2x4 mat3x2
    mat3x3 mat3x4 mat4x2 mat4x3 mat4x4""".split()
) | {n for n in _BY_NAME if n.isidentifier()}


def check_identifier(name, what: str) -> str:
    """``name`` if it is a usable WGSL identifier (ASCII), else UserError saying why not."""
    if not isinstance(name, str):
        raise UserError(f"{what} must be a string, got {name!r}")
    if not _ID.match(name) or name == "_":
        raise UserError(
            f"{what} {name!r} is not a WGSL identifier: use ASCII letters, digits and _, not starting with a digit"
        )
    if name.startswith("__"):
        raise UserError(f"{what} {name!r}: WGSL reserves identifiers starting with '__'")
    if name in _RESERVED:
        raise UserError(f"{what} {name!r} is a WGSL keyword, reserved word or type name: choose another name")
    return name


def parse_type(text: str) -> UniformType:
    """A type from its WGSL spelling: "f32", "vec3f", "vec3<f32>", "mat4x4f", ..."""
    key = text.replace(" ", "")
    if key in _BY_NAME:
        return _BY_NAME[key]
    for pattern, why in _REFUSED:
        if pattern.search(key):
            raise UserError(f"uniform type {text!r} is not supported: {why}")
    known = ", ".join(n for n in _BY_NAME if "<" not in n)
    raise UserError(f"unknown uniform type {text!r}: use one of {known}, Array(type, n) or a Struct")


def _resolve(t, where: str) -> UniformType:
    if isinstance(t, UniformType):
        return t
    if isinstance(t, str):
        try:
            return parse_type(t)
        except UserError as err:
            raise UserError(f"{where}: {err}") from None
    raise UserError(f"{where}: {t!r} is not a uniform type (use F32, VEC3F, MAT4, Array(...), a Struct or a name)")


def _sequence(value, n: int, where: str, tname: str) -> list:
    if isinstance(value, np.ndarray):
        if value.shape[:1] != (n,):
            raise UserError(f"{where}: {tname} needs {n} items, got an array of shape {value.shape}")
        return list(value)
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Sequence):
        raise UserError(f"{where}: {tname} needs a sequence of {n} items, got {type(value).__name__}")
    if len(value) != n:
        raise UserError(f"{where}: {tname} needs {n} items, got {len(value)}")
    return list(value)


# --------------------------------------------------------------------------- self-check shader


def roundtrip_wgsl(struct: Struct, template: str) -> tuple[str, list[Leaf]]:
    """A compute shader that copies every scalar of ``struct`` (bitcast to u32) into a flat array.

    ``template`` is tests/numerics/shaders/uniforms_roundtrip.wgsl (the test's); its placeholders get the
    generated struct declarations, the struct's name and one statement per scalar
    (filled by :func:`wgpurender.core.shaders.shader_variants.specialise`). Returns the source and
    the scalars in output order: comparing the output words with the values packed
    checks offsets, padding and matrix orientation against the GPU's own reading.
    """
    from wgpurender.core.shaders.shader_variants import specialise

    leaves = list(struct.leaves(expr="u"))
    copies = "\n    ".join(f"out_words[{i}] = bitcast<u32>({leaf.expr});" for i, leaf in enumerate(leaves))
    values = {"STRUCTS": wgsl_structs(struct), "STRUCT": struct.name, "COPIES": copies}
    return specialise(template, set(), values, name="uniforms_roundtrip.wgsl"), leaves
