"""The per-adapter anisotropy rule (wgpurender/core/plan/anisotropy.py) and how the plan shows it.

Expected values come from the rule as the docs state it: on a CPU adapter an anisotropic sampler gets
anisotropy 1, on a GPU it keeps the scene's value, and "scene" (the default of the library API, the
tests and the raw-path cross-checks) never changes it.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from wgpurender.core.course.samplers import SamplerSpec
from wgpurender.core.errors import UserError
from wgpurender.core.plan import AdapterFacts, resolve_plan
from wgpurender.core.plan.anisotropy import resolve_anisotropy
from wgpurender.core.scene import load_scene

FINAL = Path(__file__).resolve().parent.parent / "assets" / "scenes" / "final.toml"


@pytest.mark.parametrize(("rule", "adapter", "expected"), [
    ("auto", "CPU", 1), ("auto", "DiscreteGPU", 8), ("auto", "IntegratedGPU", 8), ("auto", None, 8),
    ("scene", "CPU", 8), ("scene", "DiscreteGPU", 8),
])
def test_rule(rule, adapter, expected):
    spec, why = resolve_anisotropy(SamplerSpec(max_anisotropy=8), rule, adapter)
    assert spec.max_anisotropy == expected
    assert spec.lod_max_clamp == 32.0 and spec.mipmap_filter == "linear"  # the mip chain is kept
    assert ("-> 1" in why) == (expected == 1 and adapter == "CPU")


def test_isotropic_sampler_is_left_alone():
    spec = SamplerSpec()
    assert resolve_anisotropy(spec, "auto", "CPU") == (spec, "")


def test_unknown_rule_is_one_clear_error():
    with pytest.raises(UserError, match="anisotropy rule 'fast'"):
        resolve_anisotropy(SamplerSpec(max_anisotropy=8), "fast", "CPU")


def test_plan_uses_and_explains_the_rule():
    """final.toml asks for anisotropy 8: 1 on a CPU adapter with the reason in --explain, 8 on a GPU."""
    scene = load_scene(FINAL)
    cpu = resolve_plan(scene, AdapterFacts("CPU"))
    gpu = resolve_plan(scene, AdapterFacts("DiscreteGPU"))
    default = resolve_plan(scene, None)  # no adapter known: the scene's value
    assert {s.spec.max_anisotropy for s in cpu.samplers} == {1}
    assert {s.spec.max_anisotropy for s in gpu.samplers} == {8}
    assert {s.spec.max_anisotropy for s in default.samplers} == {8}
    assert all(d.sampler.max_anisotropy == 1 for d in cpu.scene_pass.draws if d.sampler is not None)
    assert "anisotropy 8 -> 1 on a CPU adapter" in cpu.explain()
    assert "anisotropy 8 as the scene asks" in gpu.explain()
    assert all(t.mipmaps for t in cpu.textures)
