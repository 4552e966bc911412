"""Anisotropic filtering per adapter: the scene's value on a GPU, 1 on a CPU driver (lavapipe).

A plan knob (API-free: it reads the adapter type as a string, as wgpu reports it). Why 1 on a CPU:
lavapipe filters anisotropically in a software loop per fragment whose number of taps grows with
the footprint, i.e. with minification. Measured on a 2-core EPYC under load (docs/benchmarks.md):
final.toml's scene pass takes 3.3 s at 800x600 with anisotropy 8 and 0.25 s with 1; at 1280x720
1.0 s and 0.34 s. The smaller image is the slower one because its texels shrink more per pixel,
which is also why ``vulkan_tutorial_28.toml`` (one mip level, anisotropy 16) takes seconds at
96x72. A GPU filters anisotropically in its texture units at little cost, so it keeps the scene's
value and the scene's look. The mip chain stays as the scene asks: with anisotropy 1, a trilinear
filter over the mip chain is what keeps minified texels from aliasing.

Rules: ``"auto"`` applies the per-adapter rule: :data:`DEFAULT_ANISOTROPY`, the one default of every command,
API call, inner render function, test and plan knob, on both paths, each for its own adapter (``"auto"`` with no
adapter known keeps the scene's value). ``"scene"`` keeps the scene file's anisotropy everywhere:
:data:`REFERENCE_ANISOTROPY`, what ``verify`` (both modes), ``make_references`` and the browser export draw,
because the committed references, the C++ tutorial frames and the exported page (whose plan is made before its
adapter is known) are the scene as authored; each says so where its image differs from ``wgpurender render T``
(:func:`reference_difference`).
"""

from __future__ import annotations

import dataclasses

from wgpurender.core.course.samplers import SamplerSpec
from wgpurender.core.errors import UserError

ANISOTROPY_RULES = ("auto", "scene")
DEFAULT_ANISOTROPY = "auto"  # every command's and API call's default (core/plan/resolve.py draws every plan)
ANISOTROPY_HELP = ("auto (default): the scene's anisotropic filtering on a GPU, 1 on a CPU driver such as lavapipe "
                   "(seconds per frame there otherwise; render --explain says why); scene: always the scene's")
CPU_ANISOTROPY = 1
REFERENCE_ANISOTROPY = "scene"  # verify, make_references, the browser export: the scene as authored (see above)


def reference_difference(adapter_type: str | None) -> str:
    """What drawing with :data:`REFERENCE_ANISOTROPY` changes against ``wgpurender render T`` (the default rule) on
    an adapter of this type, in one line; '' where the two rules draw the same (a GPU, or no adapter known)."""
    if adapter_type != "CPU":
        return ""
    return (f"anisotropy: drawn as the scene asks (--anisotropy {REFERENCE_ANISOTROPY}), as the committed references, "
            f"the C++ tutorial frames and the browser page are; `wgpurender render T` on this CPU adapter draws "
            f"anisotropy {CPU_ANISOTROPY} (--anisotropy {DEFAULT_ANISOTROPY}), so scenes with anisotropic samplers "
            "differ from what it makes")


def check_applies(target: str, is_scene: bool, rule: str) -> None:
    """A rule other than the default for a stage is refused (UserError), not ignored: a stage's samplers are
    its own, the rule applies to scene files (the API and every command call this)."""
    if not is_scene and rule != DEFAULT_ANISOTROPY:
        raise UserError(f"anisotropy {rule!r} applies to scene files: stage {target!r} has its own samplers "
                        "(leave --anisotropy out)")


def resolve_anisotropy(spec: SamplerSpec, rule: str, adapter_type: str | None) -> tuple[SamplerSpec, str]:
    """(the sampler to use, why; '' when nothing needs saying)."""
    if rule not in ANISOTROPY_RULES:
        raise UserError(f"anisotropy rule {rule!r}: choose one of {', '.join(ANISOTROPY_RULES)}")
    asked = spec.max_anisotropy
    if asked <= 1 or rule == "scene" or adapter_type is None:
        return spec, ""
    if adapter_type == "CPU":
        return (dataclasses.replace(spec, max_anisotropy=CPU_ANISOTROPY),
                f"anisotropy {asked} -> {CPU_ANISOTROPY} on a CPU adapter: a software anisotropic filter costs "
                "more the more a texture is minified (seconds per frame on lavapipe); trilinear over the mip chain "
                "instead (--anisotropy scene keeps the scene's value)")
    return spec, f"anisotropy {asked} as the scene asks: a {adapter_type} adapter filters it in hardware"
