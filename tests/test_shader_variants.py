"""The variant preprocessor keeps exactly the lines a feature set asks for."""

from __future__ import annotations

import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.shaders.shader_variants import specialise

TEMPLATE = """a
#if lit
b
#if normal_map
c
#else
d
#endif
#endif
#if !lit
e
#endif
{{X}}"""


@pytest.mark.parametrize(
    "features, lines",
    [
        (set(), ["a", "e", "x"]),
        ({"lit"}, ["a", "b", "d", "x"]),
        ({"lit", "normal_map"}, ["a", "b", "c", "x"]),
        ({"normal_map"}, ["a", "e", "x"]),
    ],
)
def test_blocks(features, lines):
    assert specialise(TEMPLATE, features, {"X": "x"}).split() == lines


@pytest.mark.parametrize(
    "template, message",
    [("#if a\nx", "without #endif"), ("#endif", "without #if"), ("#ifdef a\n#endif", "unknown directive"),
     ("{{Y}}", "no value for placeholder")],
)
def test_errors(template, message):
    with pytest.raises(UserError, match=message):
        specialise(template, set(), {})
