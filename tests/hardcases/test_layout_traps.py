"""The std140 / WGSL-uniform layout traps, as a compact regression table against the packer's API.

Expected offsets are written by hand from the std140 rules (vec2 aligns to 8, vec3/vec4/mat/struct/array to 16,
array and nested-struct strides rounded up to 16). tests/test_uniforms.py covers the packer in depth (GPU round trip
included); this table only pins the five traps the issue lists. The counter-example is the naive C layout (every
member aligned to its scalar, 4 bytes, as a packed ``struct`` of floats would be): it gets every one of them wrong.
"""

from __future__ import annotations

import pytest

from wgpurender.core.shaders.uniforms import F32, MAT3, MAT4, VEC2F, VEC3F, Array, Matrix, Scalar, Struct, Vector

FOO = Struct("Foo", [("v", VEC2F)])

# name: (struct, field, expected std140 offset, expected struct size)
TRAPS = {
    "vec2 then mat4 -> mat4 at 16": (Struct("T1", [("a", VEC2F), ("m", MAT4)]), "m", 16, 80),
    "nested struct {vec2} f1, f2 -> f2 at 16": (Struct("T2", [("f1", FOO), ("f2", FOO)]), "f2", 16, 32),
    "vec3 then f32 -> f32 at 12": (Struct("T3", [("d", VEC3F), ("s", F32)]), "s", 12, 16),
    "array<f32, 4> stride 16 -> next at 64": (Struct("T4", [("w", Array(F32, 4)), ("t", F32)]), "t", 64, 80),
    "mat3x3 is 48 bytes -> next at 48": (Struct("T5", [("n", MAT3), ("s", F32)]), "s", 48, 64),
}


def naive_c_offset(struct: Struct, field: str) -> int:
    """Counter-example: a packed C struct of floats (4-byte alignment, mat3 = 36 bytes, array stride 4)."""

    def size(t) -> int:
        if isinstance(t, Scalar):
            return 4
        if isinstance(t, Vector):
            return 4 * t.n
        if isinstance(t, Matrix):
            return 4 * t.n * t.n
        if isinstance(t, Array):
            return size(t.element) * t.count
        return sum(size(f.type) for f in t.fields)

    offset = 0
    for f in struct.fields:
        if f.name == field:
            return offset
        offset += size(f.type)
    raise KeyError(field)


@pytest.mark.parametrize("trap", TRAPS)
def test_trap_offsets(trap):
    struct, field, offset, size = TRAPS[trap]
    assert struct.offsets[field] == offset
    assert struct.size == size


@pytest.mark.parametrize("trap", [t for t in TRAPS if not t.startswith("vec3 then f32")])
def test_naive_c_layout_gets_the_trap_wrong(trap):
    """The naive layout disagrees on every trap except vec3+f32, where std140 packs the f32 into the padding."""
    struct, field, offset, _ = TRAPS[trap]
    assert naive_c_offset(struct, field) != offset


def test_array_stride_and_mat3_size():
    assert Array(F32, 7).stride == 16 and Array(F32, 7).size == 112
    assert Array(VEC2F, 3).stride == 16
    assert MAT3.size == 48 and MAT4.size == 64
