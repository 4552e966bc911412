"""Every plan goes through resolve_plan, and the anisotropy rule has one default (issue 32 item 1).

Before: ``build_plan``, ``plan_scene_file`` and ``RenderPlan.with_knobs`` built plans without ``resolve_plan``, and
the inner render functions defaulted to anisotropy "scene" where the CLI and API said "auto", so the
implementation matrix and the tests drew another image than ``wgpurender render T`` on a CPU adapter.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import wgpurender.core.plan.resolve as resolve_module
from wgpurender.core.plan import AdapterFacts, resolve_plan
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY, reference_difference

REPO = Path(__file__).resolve().parent.parent
FINAL = REPO / "assets" / "scenes" / "final.toml"  # anisotropy 8 in its material samplers
SOURCES = [p for folder in ("wgpurender", "tests", "benchmarks") for p in sorted((REPO / folder).rglob("*.py"))]


def _calls(tree: ast.AST, name: str):
    """(call node, the names of the functions it is inside) for each call of ``name`` (plain or attribute)."""
    def walk(node, inside):
        for child in ast.iter_child_nodes(node):
            scope = (*inside, child.name) if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)) else inside
            if isinstance(child, ast.Call):
                f = child.func
                called = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else None
                if called == name:
                    yield child, inside
            yield from walk(child, scope)
    yield from walk(tree, ())


def test_build_plan_is_called_by_resolve_plan_only():
    """An AST check over the package, the tests and the benchmarks: the one call of build_plan is in
    resolve_plan, and nothing constructs a RenderPlan but build.py."""
    callers, constructors = [], []
    for path in SOURCES:
        tree = ast.parse(path.read_text(), str(path))
        rel = path.relative_to(REPO).as_posix()
        callers += [(rel, inside) for _, inside in _calls(tree, "build_plan")]
        callers += [(rel, ("plan_scene_file",)) for _ in _calls(tree, "plan_scene_file")]
        constructors += [rel for _, _ in _calls(tree, "RenderPlan")]
    assert callers == [("wgpurender/core/plan/resolve.py", ("resolve_plan",))]
    assert set(constructors) <= {"wgpurender/core/plan/build.py"}


def test_with_knobs_and_the_api_resolve(monkeypatch):
    """A sentinel: with_knobs and the API's plan() each go through resolve_plan (counted), and a plan changed by
    with_knobs is the plan resolve_plan gives for the same arguments."""
    from wgpurender import api

    seen = []
    real = resolve_module.resolve_plan

    def counting(*args, **kwargs):
        seen.append(kwargs)
        return real(*args, **kwargs)

    monkeypatch.setattr(resolve_module, "resolve_plan", counting)
    monkeypatch.setattr("wgpurender.core.plan.resolve_plan", counting)
    cpu = AdapterFacts("CPU", frozenset(), "llvmpipe", "Vulkan")
    plan = real(FINAL, None, size=(64, 48))
    changed = plan.with_knobs(adapter=cpu, post_fuse=False)
    assert len(seen) == 1 and seen[0]["post_fuse"] is False
    assert changed == real(FINAL, cpu, size=(64, 48), post_fuse=False)
    api.plan(FINAL, size=(64, 48))
    assert len(seen) == 2


def test_one_anisotropy_default():
    """No function of the package writes the anisotropy default as a literal: every ``anisotropy`` parameter
    defaults to DEFAULT_ANISOTROPY (one home), and the plan's knob does too."""
    literal = []
    for path in (REPO / "wgpurender").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                args = node.args
                pairs = [*zip(args.args[len(args.args) - len(args.defaults):], args.defaults, strict=True),
                         *zip(args.kwonlyargs, args.kw_defaults, strict=True)]
                literal += [f"{path.name}:{node.name}" for a, d in pairs
                            if a.arg == "anisotropy" and isinstance(d, ast.Constant)]
            if isinstance(node, ast.AnnAssign) and getattr(node.target, "id", "") == "anisotropy":
                if isinstance(node.value, ast.Constant) and isinstance(node.value.value, str):
                    literal.append(f"{path.name}: a field anisotropy = {node.value.value!r}")
    assert literal == []


def test_inner_renderers_draw_what_render_draws(ctx):
    """The wgpu path's inner render function, with no anisotropy given, draws the plan the CLI's default draws
    on this adapter: final.toml asks for anisotropy 8; a CPU adapter draws 1 (the rule), a GPU 8."""
    from wgpurender.wgpu_path.scene import load_renderer

    inner = load_renderer(FINAL, ctx, size=(32, 24)).plan
    cli = resolve_plan(FINAL, ctx.adapter_facts(), size=(32, 24), anisotropy=DEFAULT_ANISOTROPY)
    assert inner == cli
    want = 1 if ctx.adapter.info["adapter_type"] == "CPU" else 8
    assert {s.spec.max_anisotropy for s in inner.samplers} == {want}


@pytest.mark.parametrize(("adapter_type", "says"), [("CPU", True), ("DiscreteGPU", False), (None, False)])
def test_reference_renders_say_what_they_change(adapter_type, says):
    """verify, make_references and the matrix draw the scene's anisotropy; they say so exactly where that
    differs from ``render T`` (a CPU adapter, where the rule draws 1)."""
    note = reference_difference(adapter_type)
    assert bool(note) is says
    if says:
        assert "anisotropy 1" in note and "--anisotropy scene" in note
