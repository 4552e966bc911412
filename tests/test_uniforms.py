"""The uniform layout packer: the course's std140 traps, bad definitions, and a GPU round trip.

Offset tables are written out by hand from the std140 / WGSL uniform rules (not
computed by the packer). The round trip packs values, lets a compute shader read
every scalar through the generated WGSL declaration, and compares the bits it
writes back with the Python values, exactly (0 ulp): a wrong offset, missing
padding or a transposed matrix reads a different scalar.
"""

from __future__ import annotations

import numpy as np
import pytest
import wgpu
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from numerics.wgsl import load_wgsl as load_test_wgsl

from wgpurender.core.errors import UserError
from wgpurender.core.shaders.uniforms import (
    F32,
    I32,
    MAT3,
    MAT4,
    U32,
    VEC2F,
    VEC2I,
    VEC3F,
    VEC3U,
    VEC4F,
    Array,
    Matrix,
    Struct,
    Vector,
    roundtrip_wgsl,
    wgsl_structs,
)
from wgpurender.wgpu_path.device.shaders import create_shader_module

FOO = Struct("Foo", [("v", VEC2F)])

# name -> (struct, expected top-level offsets, expected size), from the course's alignment chapter.
TRAPS = {
    # vec2 then mat4: the mat4 is vec4-aligned, at 16 not 8 (the course's vanished square).
    "vec2_then_mat4": (
        Struct("Ubo", [("foo", VEC2F), ("model", MAT4), ("view", MAT4), ("proj", MAT4)]),
        {"foo": 0, "model": 16, "view": 80, "proj": 144},
        208,
    ),
    # struct Foo { vec2 v; } f1, f2: a nested struct is 16-aligned and 16-sized, f2 at 16 not 8.
    "nested_vec2_structs": (Struct("Nested", [("f1", FOO), ("f2", FOO)]), {"f1": 0, "f2": 16}, 32),
    # vec3 then f32: the f32 sits in the vec3's last 4 bytes of padding.
    "vec3_then_f32": (Struct("Light", [("dir", VEC3F), ("ambient", F32)]), {"dir": 0, "ambient": 12}, 16),
    # f32 and vec3 arrays: stride 16 each.
    "arrays": (
        Struct("Arrays", [("weights", Array(F32, 3)), ("points", Array(VEC3F, 2)), ("tail", F32)]),
        {"weights": 0, "points": 48, "tail": 80},
        96,
    ),
    # mat3x3 = 3 columns padded to vec4: 48 bytes; the next scalar at 48.
    "mat3_then_f32": (Struct("Normal", [("normal", MAT3), ("scale", F32)]), {"normal": 0, "scale": 48}, 64),
    # vec2 after a vec3 does not fit in its padding (needs 8 bytes at an 8-aligned offset).
    "vec3_then_vec2": (Struct("V32", [("a", VEC3F), ("b", VEC2F), ("c", F32)]), {"a": 0, "b": 16, "c": 24}, 32),
}


@pytest.mark.parametrize("name", TRAPS)
def test_course_traps_offsets(name):
    struct, offsets, size = TRAPS[name]
    assert struct.offsets == offsets
    assert struct.size == size


def test_nested_and_array_strides():
    """Nested fields and array elements, absolute offsets (hand-computed)."""
    flat = TRAPS["nested_vec2_structs"][0].flat_offsets()
    assert flat == {"f1": 0, "f1.v": 0, "f2": 16, "f2.v": 16}
    arrays = TRAPS["arrays"][0]
    assert arrays.field("weights").type.stride == 16 and arrays.field("points").type.stride == 16
    assert [arrays.flat_offsets()[f"weights[{i}]"] for i in range(3)] == [0, 16, 32]
    assert [arrays.flat_offsets()[f"points[{i}]"] for i in range(2)] == [48, 64]
    assert (MAT3.size, MAT3.align, MAT4.size) == (48, 16, 64)


def test_pack_bytes_by_hand():
    """Packed bytes at hand-computed positions: mat3 column-major with zero padding, vec3+f32."""
    m = np.arange(9, dtype=np.float64).reshape(3, 3)  # m[r, c] = 3r + c
    data = np.frombuffer(TRAPS["mat3_then_f32"][0].pack({"normal": m, "scale": 7.0}), dtype="<f4")
    expected = [0, 3, 6, 0, 1, 4, 7, 0, 2, 5, 8, 0, 7, 0, 0, 0]  # columns, each padded to 4 floats
    assert data.tolist() == expected
    light = np.frombuffer(TRAPS["vec3_then_f32"][0].pack({"dir": (1, 2, 3), "ambient": 0.5}), dtype="<f4")
    assert light.tolist() == [1, 2, 3, 0.5]
    vec2_mat4 = np.frombuffer(
        TRAPS["vec2_then_mat4"][0].pack({"foo": (9, 8), "model": np.eye(4), "view": np.eye(4), "proj": np.eye(4)}),
        dtype="<f4",
    )
    assert vec2_mat4[:4].tolist() == [9, 8, 0, 0] and vec2_mat4[4:20].tolist() == np.eye(4).ravel().tolist()


def test_dynamic_offset_stride():
    obj = Struct("Obj", [("world", MAT4), ("normal", MAT3)])
    assert obj.size == 112 and obj.stride(256) == 256 and obj.stride(32) == 128
    data = obj.pack_many([{"world": np.eye(4) * k, "normal": np.eye(3)} for k in (1, 2)], 256)
    assert len(data) == 512 and np.frombuffer(data, "<f4")[64] == 2.0


def test_wgsl_declarations_text_and_compile(ctx):
    """The generated declarations pad where WGSL would not, and naga accepts them in uniform space."""
    text = wgsl_structs(TRAPS["nested_vec2_structs"][0])
    assert text.index("struct Foo") < text.index("struct Nested")
    assert "@size(16) v: vec2f" in text
    assert "@size(16) foo: vec2f" in TRAPS["vec2_then_mat4"][0].wgsl()
    template = load_test_wgsl("uniforms_roundtrip.wgsl")
    for struct, _, _ in TRAPS.values():
        code, _ = roundtrip_wgsl(struct, template)
        create_shader_module(ctx.device, "uniforms_roundtrip.wgsl", code)


_S_X = Struct("S", [("x", F32)])
_S_Y = Struct("S", [("y", F32)])


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Struct("S", [("a", "vec5f")]), "unknown uniform type"),
        (lambda: Struct("S", [("a", "bool")]), "not host-shareable"),
        (lambda: Struct("S", [("a", "f16")]), "shader-f16"),
        (lambda: Struct("S", [("a", "mat2x2f")]), "only mat3x3f and mat4x4f"),
        (lambda: Struct("S", [("a", 3.0)]), "not a uniform type"),
        (lambda: Array(F32, 0), "length must be an integer >= 1"),
        (lambda: Array(F32, 2.5), "length must be an integer >= 1"),
        (lambda: Struct("2abc", [("a", F32)]), "not a WGSL identifier"),
        (lambda: Struct("S", [("my field", F32)]), "not a WGSL identifier"),
        (lambda: Struct("S", [("fn", F32)]), "keyword"),
        (lambda: Struct("S", [("__x", F32)]), "reserves"),
        (lambda: Struct("vec3f", [("a", F32)]), "type name"),
        (lambda: Struct("S", []), "non-empty list"),
        (lambda: Struct("S", [("a", F32), ("a", U32)]), "declared twice"),
        (lambda: Struct("S", [("a",)]), r"\(name, type\) pair"),
        (lambda: wgsl_structs(Struct("T", [("a", _S_X), ("b", _S_Y)])), "both named"),
    ],
)
def test_bad_definitions_raise_user_error(make, message):
    with pytest.raises(UserError, match=message):
        make()


@pytest.mark.parametrize(
    "values, message",
    [
        ({"a": 1.0}, "missing"),
        ({"a": 1.0, "v": (1, 2, 3), "m": np.eye(4), "n": -1, "x": 2}, "unknown x"),
        ({"a": 1.0, "v": (1, 2), "m": np.eye(4), "n": 1}, "needs 3 items"),
        ({"a": 1.0, "v": (1, 2, 3), "m": np.eye(3), "n": 1}, "4x4 matrix"),
        ({"a": 1.0, "v": (1, 2, 3), "m": np.eye(4), "n": -1}, "outside the u32 range"),
        ({"a": 1.0, "v": (1, 2, 3), "m": np.eye(4), "n": 1.5}, "needs an integer"),
        ({"a": "x", "v": (1, 2, 3), "m": np.eye(4), "n": 1}, "needs a number"),
        ({"a": 1e39, "v": (1, 2, 3), "m": np.eye(4), "n": 1}, "f32 range"),
    ],
)
def test_bad_values_raise_user_error(values, message):
    struct = Struct("P", [("a", F32), ("v", VEC3F), ("m", MAT4), ("n", U32)])
    with pytest.raises(UserError, match=message):
        struct.pack(values)


# --------------------------------------------------------------------------- GPU round trip


def _run_roundtrip(ctx, struct: Struct, values: dict) -> np.ndarray:
    """Pack ``values``, let the generated compute shader copy every scalar out, return the u32 words."""
    code, leaves = roundtrip_wgsl(struct, load_test_wgsl("uniforms_roundtrip.wgsl"))
    dev = ctx.device
    module = create_shader_module(dev, "uniforms_roundtrip.wgsl", code)
    pipeline = dev.create_compute_pipeline(layout="auto", compute={"module": module, "entry_point": "main"})
    ubo = dev.create_buffer_with_data(data=struct.pack(values), usage=wgpu.BufferUsage.UNIFORM)
    out_size = 4 * len(leaves)
    out = dev.create_buffer(size=out_size, usage=wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_SRC)
    readback = dev.create_buffer(size=out_size, usage=wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.MAP_READ)
    bind_group = dev.create_bind_group(
        layout=pipeline.get_bind_group_layout(0),
        entries=[
            {"binding": 0, "resource": {"buffer": ubo, "offset": 0, "size": struct.size}},
            {"binding": 1, "resource": {"buffer": out, "offset": 0, "size": out_size}},
        ],
    )
    enc = dev.create_command_encoder()
    cpass = enc.begin_compute_pass()
    cpass.set_pipeline(pipeline)
    cpass.set_bind_group(0, bind_group)
    cpass.dispatch_workgroups(1)
    cpass.end()
    enc.copy_buffer_to_buffer(out, 0, readback, 0, out_size)
    ctx.queue.submit([enc.finish()])
    ctx.map_read(readback)  # on this thread (wgpu_path/device/context.py), as every readback
    words = np.frombuffer(readback.read_mapped(), dtype="<u4").copy()
    readback.unmap()
    return words, leaves


def _expected_words(values: dict, leaves) -> np.ndarray:
    """The bits of every scalar, looked up in the Python values by path (matrices as m[row][col])."""
    words = []
    for leaf in leaves:
        v = values
        for key in leaf.path:
            v = v[key]
        words.append(np.asarray(v, dtype=leaf.scalar.dtype).view("<u4").item())
    return np.array(words, dtype="<u4")


def _check_roundtrip(ctx, struct, values):
    words, leaves = _run_roundtrip(ctx, struct, values)
    expected = _expected_words(values, leaves)
    bad = np.nonzero(words != expected)[0]
    assert bad.size == 0, (
        f"{struct}: first mismatch at {leaves[bad[0]].path}: {words[bad[0]]:#x} != {expected[bad[0]]:#x}"
    )


def _distinct_values(t, counter):
    """Every scalar a different small number (1, 2, 3, ...), so any misplaced read shows."""

    def take(n):
        counter[0] += n
        return list(range(counter[0] - n + 1, counter[0] + 1))

    if isinstance(t, Struct):
        return {f.name: _distinct_values(f.type, counter) for f in t.fields}
    if isinstance(t, Array):
        return [_distinct_values(t.element, counter) for _ in range(t.count)]
    if isinstance(t, Matrix):
        return np.array(take(t.n * t.n), dtype=np.float64).reshape(t.n, t.n)
    if isinstance(t, Vector):
        return [float(x) if t.scalar is F32 else x for x in take(t.n)]
    return float(take(1)[0]) if t is F32 else take(1)[0]


@pytest.mark.parametrize("name", TRAPS)
def test_course_traps_roundtrip_on_gpu(ctx, name):
    struct = TRAPS[name][0]
    _check_roundtrip(ctx, struct, _distinct_values(struct, [0]))


# Random definitions: scalars, vectors, matrices, arrays (nested too) and nested structs.
_LEAF_TYPES = [F32, I32, U32, VEC2F, VEC3F, VEC4F, VEC2I, VEC3U, MAT3, MAT4]
_floats = st.floats(width=32, allow_nan=False, allow_infinity=False, allow_subnormal=False)


@st.composite
def _types(draw, depth=0, names=None):
    choices = ["leaf", "leaf", "leaf"] + (["array", "struct"] if depth < 2 else [])
    kind = draw(st.sampled_from(choices))
    if kind == "leaf":
        return draw(st.sampled_from(_LEAF_TYPES))
    if kind == "array":
        return Array(draw(_types(depth + 1, names)), draw(st.integers(1, 3)))
    return draw(_structs(depth + 1, names))


@st.composite
def _structs(draw, depth=0, names=None):
    names = names if names is not None else [0]
    names[0] += 1
    name = f"S{names[0]}"
    n = draw(st.integers(1, 4))
    return Struct(name, [(f"f{i}", draw(_types(depth, names))) for i in range(n)])


def _values_for(t):
    """A strategy for Python values of type ``t`` (nested lists/dicts, like a user would write)."""
    if isinstance(t, Struct):
        return st.fixed_dictionaries({f.name: _values_for(f.type) for f in t.fields})
    if isinstance(t, Array):
        return st.lists(_values_for(t.element), min_size=t.count, max_size=t.count)
    if t in (MAT3, MAT4):
        row = st.lists(_floats, min_size=t.n, max_size=t.n)
        return st.lists(row, min_size=t.n, max_size=t.n)
    scalar = getattr(t, "scalar", t)
    one = {"f32": _floats, "i32": st.integers(-(2**31), 2**31 - 1), "u32": st.integers(0, 2**32 - 1)}[scalar.name]
    return st.lists(one, min_size=t.n, max_size=t.n) if hasattr(t, "n") else one


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_random_structs_roundtrip_on_gpu(ctx, data):
    """Random definitions and values survive pack -> uniform buffer -> WGSL read, bit for bit.

    Subnormal floats are left out: WGSL lets implementations flush them to zero.
    """
    struct = data.draw(_structs())
    values = data.draw(_values_for(struct))
    _check_roundtrip(ctx, struct, values)
