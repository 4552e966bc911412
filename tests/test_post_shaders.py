"""Effect parameter structs are generated from the GPU-free specs, so Python and WGSL cannot disagree.

Expected values are written here from the WGSL uniform layout rules (f32: 4 bytes, struct size rounded
up to 16) and from the specs' parameter lists, not taken from the generator's output.
"""

from __future__ import annotations

import re
import struct
from pathlib import Path

import pytest

from wgpurender.core.course.effects import EFFECTS, make_step
from wgpurender.wgpu_path.post import PostChain
from wgpurender.wgpu_path.post.shaders import pack_pass, params_struct, pass_source

SHADERS = Path(__file__).resolve().parent.parent / "shaders_wgsl"


@pytest.mark.parametrize("name", sorted(EFFECTS))
def test_effect_files_declare_no_parameter_struct_or_binding(name):
    text = (SHADERS / f"post_{name}.wgsl").read_text()
    assert not re.search(r"^\s*struct \w*Params", text, re.M), "parameter structs are generated"
    assert "var<uniform>" not in text and "@binding(2)" not in text


@pytest.mark.parametrize("name", sorted(n for n in EFFECTS if EFFECTS[n].params))
def test_struct_has_one_f32_per_parameter_in_spec_order(name):
    spec = EFFECTS[name]
    generated = params_struct(spec)
    assert list(generated.offsets) == [p.name if not p.choices else f"{p.name}_index" for p in spec.params]
    assert list(generated.offsets.values()) == [4 * i for i in range(len(spec.params))]
    assert generated.size == 16  # at most 4 floats, rounded up to the uniform struct alignment
    for field in generated.offsets:
        assert f"params.{field}" in (SHADERS / f"post_{name}.wgsl").read_text(), f"the WGSL reads {field}"


def test_fused_pass_packs_each_step_in_its_own_member():
    """tonemap (exposure 2, reinhard = choice 1) + vignette (0.25, 0.5, 0.75): s0 at 0, s1 at 16."""
    steps = [make_step("tonemap", exposure=2.0, operator="reinhard"),
             make_step("vignette", strength=0.25, radius=0.5, softness=0.75)]
    (p,), _ = PostChain(steps).plan("rgba16float", "rgba16float", (4, 4))
    data = pack_pass(p)
    assert len(data) == 32
    assert struct.unpack("<2f", data[0:8]) == (2.0, 1.0)
    assert struct.unpack("<3f", data[16:28]) == (0.25, 0.5, 0.75)
    source = pass_source(p)
    assert "struct PassParams" in source and "s0: TonemapParams" in source and "s1: VignetteParams" in source
    assert "c = tonemap_pixel(c, pos, size, params.s0);" in source
    assert source.index("tonemap_pixel(c,") < source.index("vignette_pixel(c,")
